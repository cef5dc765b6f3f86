-- test_curve.lua: bsfit.Curve checked against mathematics
local T = require "tap"
local bs = require "bsfit"

local r2 = math.sqrt(2) / 2

local function quarter_circle()
  return bs.curve.new{degree = 2, knots = {0, 0, 0, 1, 1, 1},
                      control_points = {{1, 0}, {1, 1}, {0, 1}}, weights = {1, r2, 1}}
end

T.test("a rational quadratic quarter circle has radius 1 everywhere (NURBS Book ex. 7.1)", function()
  local C = quarter_circle()
  T.eq(C:kind(), "nurbs"); T.ok(C:is_rational())
  for i = 0, 50 do
    local x, y = C:eval(i / 50)
    T.near(x * x + y * y, 1, 1e-14, "radius at " .. i / 50)
  end
  local x, y = C:eval(0.5)
  T.near(x, r2, 1e-15); T.near(y, r2, 1e-15, "midpoint at 45 degrees")
  x, y = C:eval(1)
  T.near(x, 0, 1e-15); T.near(y, 1, 1e-15)
end)

-- Greville abscissae g_i = (u_{i+1} + ... + u_{i+p}) / p reproduce the identity:
-- sum_i g_i N_{i,p}(t) = t (linear precision), whatever the knots.
T.test("control points at the Greville abscissae reproduce x(t) = t", function()
  local U = {0, 0, 0, 0, 0.1, 0.15, 0.6, 0.8, 1, 1, 1, 1}
  local p, n = 3, #U - 4
  local P = {}
  for i = 1, n do
    local g = (U[i + 1] + U[i + 2] + U[i + 3]) / p
    P[i] = {g, 1}
  end
  local C = bs.curve.new{degree = p, knots = U, control_points = P}
  T.eq(C:kind(), "bspline"); T.eq(C:count(), n); T.eq(C:dim(), 2)
  for k = 0, 100 do
    local t = k / 100
    local x, y = C:eval(t)
    T.near(x, t, 1e-14, "x(" .. t .. ")")
    T.near(y, 1, 1e-14, "partition of unity at " .. t)
  end
end)

T.test("Bezier: de Casteljau equals the Bernstein sum computed by hand", function()
  local B = bs.bezier.new{control_points = {{0, 0}, {1, 2}, {3, 3}, {4, 0}}}
  T.eq(B:kind(), "bezier"); T.eq(B:degree(), 3)
  local x, y = B:eval(0.5)
  T.near(x, 2); T.near(y, 15 / 8)
  local t = 0.3
  local b = {(1 - t) ^ 3, 3 * t * (1 - t) ^ 2, 3 * t * t * (1 - t), t ^ 3}
  x, y = B:eval(t)
  T.near(x, b[2] + 3 * b[3] + 4 * b[4]); T.near(y, 2 * b[2] + 3 * b[3])
end)

T.test("periodic cubic: C(t_i) = (P_i + 4 P_{i+1} + P_{i+2}) / 6 and C has period 1", function()
  local Q = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {-0.5, 0.5}}
  local C = bs.curve.new{degree = 3, periodic = true, control_points = Q}
  local N = #Q
  T.ok(C:is_periodic()); T.eq(C:distinct(), N); T.eq(C:count(), N + 3); T.eq(#C, N + 3)
  local a, b = C:domain()
  T.eq(a, 0); T.eq(b, 1)
  for i = 0, N - 1 do
    local P0, P1, P2 = Q[i % N + 1], Q[(i + 1) % N + 1], Q[(i + 2) % N + 1]
    local x, y = C:eval(i / N)
    T.near(x, (P0[1] + 4 * P1[1] + P2[1]) / 6, 1e-14, "x at knot " .. i)
    T.near(y, (P0[2] + 4 * P1[2] + P2[2]) / 6, 1e-14, "y at knot " .. i)
  end
  for _, t in ipairs{0.05, 0.37, 0.9} do
    local x0, y0 = C:eval(t)
    local x1, y1 = C:eval(t + 1)
    T.near(x1, x0, 1e-13); T.near(y1, y0, 1e-13)
  end
  -- the same curve given by its expanded knot vector
  local K = bs.knots.periodic{degree = 3, count = N}
  local D = bs.curve.new{degree = 3, periodic = true, control_points = Q, knots = K}
  local kc, kd = C:knots():values(), D:knots():values()
  T.eq(#kd, #kc)
  for i = 1, #kc do T.near(kd[i], kc[i], 1e-15, "knot " .. i) end
end)

T.test("set_control_point on a periodic curve moves the wrapped copy too", function()
  local Q = {{0, 0}, {1, 0}, {1, 1}, {0, 1}}
  local C = bs.curve.new{degree = 3, periodic = true, control_points = Q}
  C:set_control_point(2, 5, 6)
  local x, y = C:control_point(6)
  T.eq(x, 5); T.eq(y, 6)
  C:set_control_point(7, -1, -2) -- the wrapped copy of point 3 names point 3
  x, y = C:control_point(3)
  T.eq(x, -1); T.eq(y, -2)
  local x0, y0 = C:eval(0)
  local x1, y1 = C:eval(1)
  T.near(x0, x1, 1e-14); T.near(y0, y1, 1e-14)
  T.raises("bad argument #4 to 'set_control_point' (too many coordinates (curve has 2))",
           function() C:set_control_point(1, 1, 2, 3) end)
  T.raises("bad argument #2 to 'set_control_point' (coordinate is not finite)",
           function() C:set_control_point(1, 0 / 0, 2) end)
end)

T.test("accessors return copies: knots, control_points, weights", function()
  local C = quarter_circle()
  local K = C:knots()
  T.eq(getmetatable(K).__name, "bsfit.Knots")
  T.eq(K:degree(), 2); T.eq(#K, 6)
  local P = C:control_points()
  T.eq(#P, 3); T.eq(select(2, P:get(2)), 1)
  local w = C:weights()
  T.near(w:get(2), r2)
  T.eq(bs.bezier.new{control_points = {{0, 0}, {1, 1}}}:weights(), nil)
  local x, y = C:control_point(-1)
  T.eq(x, 0); T.eq(y, 1)
end)

T.test("eval_many equals eval at every parameter", function()
  local C = quarter_circle()
  local u = bs.vector.new(101)
  for i = 1, 101 do u:set(i, (i - 1) / 100) end
  local P = C:eval_many(u)
  T.eq(#P, 101); T.eq(P:dim(), 2)
  for i = 1, 101, 10 do
    local x, y = P:get(i)
    local ex, ey = C:eval((i - 1) / 100)
    T.eq(x, ex); T.eq(y, ey)
  end
  T.eq(#C:eval_many{0, 0.5}, 2, "a table of parameters works too")
end)

T.test("copy is deep; <close> and close() release, later use raises, __gc is idempotent", function()
  local C = quarter_circle()
  local D = C:copy()
  D:set_control_point(1, 2, 0)
  T.eq((C:control_point(1)), 1)
  do
    local E <close> = C:copy()
    T.ok(E:eval(0.5))
    D = E
  end
  T.raises("attempt to use a closed curve", function() D:eval(0.5) end)
  T.eq(tostring(D), "bsfit.Curve (closed)")
  D:close(); D:close()
  D = nil
  collectgarbage(); collectgarbage()
  T.ok(tostring(C):match("^bsfit%.Curve%(deg=2, n=3, dim=2%): "), tostring(C))
end)

T.test("misuse raises with the argument named", function()
  local C = quarter_circle()
  local P = bs.points.new{{0, 0}}
  T.raises("bad argument #1 to 'eval' (bsfit.Curve expected, got bsfit.Points)", function() C.eval(P, 0) end)
  T.raises("bad argument #1 to 'eval' (parameter is not finite)", function() C:eval(0 / 0) end)
  T.raises("bad argument #1 to 'eval' (number expected, got string)", function() C:eval("x") end)
  T.raises("bad argument #1 to 'eval_many' (parameter u[1] is not finite)", function() C:eval_many{0, 0 / 0} end)
  local cp = {{0, 0}, {1, 1}, {2, 0}}
  T.raises("bad argument #1 to 'new' (unknown option 'control_pts')",
           function() bs.curve.new{degree = 2, control_pts = cp} end)
  T.raises("bad argument #1 to 'new' (field 'control_points' is required)",
           function() bs.curve.new{degree = 2} end)
  T.raises("bad argument #1 to 'new' (degree 3 needs at least 4 control points, got 3)",
           function() bs.curve.new{degree = 3, control_points = cp} end)
  T.raises("bad argument #1 to 'new' (degree 2 with 3 control points needs 6 knots, got 5)",
           function() bs.curve.new{degree = 2, control_points = cp, knots = {0, 0, 0, 1, 1}} end)
  T.raises("bad argument #1 to 'new' (knots decrease at knot 4 (0.5 < 1))",
           function() bs.curve.new{degree = 2, control_points = cp, knots = {0, 0, 1, 0.5, 1, 1}} end)
  T.raises("bad argument #1 to 'new' (2 weights for 3 control points)",
           function() bs.curve.new{degree = 2, control_points = cp, weights = {1, 1}} end)
  T.raises("bad argument #1 to 'new' (weight 2 is -1 (must be positive and finite))",
           function() bs.curve.new{degree = 2, control_points = cp, weights = {1, -1, 1}} end)
  T.raises("bad argument #1 to 'new' (point 2 has a non-finite coordinate)",
           function() bs.curve.new{degree = 1, control_points = {{0, 0}, {0 / 0, 1}}} end)
  T.raises("bad argument #1 to 'new' (knots of degree 3 for a curve of degree 2)",
           function() bs.curve.new{degree = 2, control_points = cp, knots = bs.knots.clamped{degree = 3, count = 4}} end)
  T.raises("bad argument #1 to 'new' (field 'periodic' must be a boolean)",
           function() bs.curve.new{degree = 2, control_points = cp, periodic = 1} end)
  T.raises("bad argument #1 to 'control_point' (index 4 out of range 1..3)", function() C:control_point(4) end)
end)

T.test("deriv agrees with central finite differences (orders 1 and 2)", function()
  local C = bs.curve.new{degree = 3, knots = {0, 0, 0, 0, 0.4, 1, 1, 1, 1},
                         control_points = {{0, 0}, {1, 3}, {2, -1}, {4, 2}, {5, 0}}, weights = {1, 2, 0.5, 1, 1}}
  local h = 1e-5
  for _, t in ipairs{0.1, 0.3, 0.55, 0.9} do
    local xp, yp = C:eval(t + h)
    local xm, ym = C:eval(t - h)
    local x0, y0 = C:eval(t)
    local dx, dy = C:deriv(t)
    T.near(dx, (xp - xm) / (2 * h), 1e-6, "x' at " .. t)
    T.near(dy, (yp - ym) / (2 * h), 1e-6, "y' at " .. t)
    local ddx, ddy = C:deriv(t, 2)
    T.near(ddx, (xp - 2 * x0 + xm) / (h * h), 1e-3, "x'' at " .. t)
    T.near(ddy, (yp - 2 * y0 + ym) / (h * h), 1e-3, "y'' at " .. t)
    local ex, ey = C:eval(t)
    local zx, zy = C:deriv(t, 0)
    T.near(zx, ex, 1e-14); T.near(zy, ey, 1e-14)
  end
  T.raises("bad argument #2 to 'deriv' (derivative order must be >= 0)", function() C:deriv(0.5, -1) end)
end)

T.test("insert and refine keep the curve as a point set and parametrisation", function()
  local C = quarter_circle()
  local D = C:insert(0.3, 2)
  T.eq(D:count(), C:count() + 2); T.eq(C:count(), 3, "C unchanged")
  T.eq(D:knots():multiplicity(0.3), 2)
  local R = C:refine{0.2, 0.5, 0.5, 0.7}
  T.eq(R:count(), 7)
  for i = 0, 20 do
    local t = i / 20
    local x, y = C:eval(t)
    local dx, dy = D:eval(t)
    local rx, ry = R:eval(t)
    T.near(dx, x, 1e-14); T.near(dy, y, 1e-14)
    T.near(rx, x, 1e-14); T.near(ry, y, 1e-14)
  end
  T.raises({match = "^bad argument #1 to 'insert' %(.*outside"}, function() C:insert(2) end)
  T.raises({match = "^bad argument #2 to 'insert' %(.*multiplicity"}, function() C:insert(0.5, 3) end)
end)

T.test("JSON: docs/formats.md keys, and from_json(to_json(C)) is the same curve", function()
  local C = quarter_circle()
  local s = C:to_json()
  for _, key in ipairs{'"type"%s*:%s*"nurbs"', '"degree"%s*:%s*2', '"dim"%s*:%s*2', '"periodic"%s*:%s*false',
                       '"knots"%s*:', '"control_points"%s*:', '"weights"%s*:', '"domain"%s*:'} do
    T.ok(s:find(key), "JSON has " .. key .. ": " .. s)
  end
  local D = bs.curve.from_json(s)
  T.eq(D:kind(), "nurbs")
  T.eq(D:control_points():bytes(), C:control_points():bytes(), "%.17g round trip")
  T.eq(D:weights():bytes(), C:weights():bytes())
  local Pc = bs.curve.new{degree = 3, periodic = true, control_points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}}}
  local Pd = bs.curve.from_json(Pc:to_json())
  T.ok(Pd:is_periodic()); T.eq(Pd:distinct(), 4)
  local path = os.tmpname() .. ".json"
  T.eq(C:write(path), C)
  local E = bs.curve.read(path)
  T.eq(E:to_json(), s)
  os.remove(path)
  T.fails("EFORMAT", bs.curve.from_json, "{\"type\": \"bspline\"")
  T.fails("EIO", bs.curve.read, path .. ".missing")
  T.raises("bad argument #1 to 'write' (file name must end in .json, .svg, .iges, .igs, .step, .stp, .dxf or .csv)", function() C:write("c.txt") end)
end)
