-- test_fitter.lua: parameters, knot placement and bsfit.Fitter, checked against mathematics
local T = require "tap"
local bs = require "bsfit"

-- m parameters equally spaced on [0, 1] (open) or [0, 1) (closed)
local function grid(m, closed)
  local u = bs.vector.new(m)
  local den = closed and m or m - 1
  for i = 1, m do u:set(i, (i - 1) / den) end
  return u
end

local function control_near(A, B, tol, msg)
  T.eq(#A, #B, msg .. ": count")
  for i = 1, #A do
    local ax, ay = A:get(i)
    local bx, by = B:get(i)
    T.near(ax, bx, tol, msg .. " x" .. i); T.near(ay, by, tol, msg .. " y" .. i)
  end
end

T.test("params: chord, centripetal and uniform by hand; closed adds the closing chord", function()
  local P = bs.points.new{{0, 0}, {3, 0}, {3, 4}}
  local u = bs.params(P, "chord")
  T.eq(u:get(1), 0); T.near(u:get(2), 3 / 7); T.eq(u:get(3), 1)
  u = bs.params(P, "chord", {closed = true})
  T.eq(u:get(1), 0); T.near(u:get(2), 3 / 12); T.near(u:get(3), 7 / 12)
  u = bs.params(P, "centripetal")
  T.near(u:get(2), math.sqrt(3) / (math.sqrt(3) + 2))
  u = bs.params({{0, 0}, {1, 1}, {5, 5}}, "uniform")
  T.near(u:get(2), 0.5)
  T.eq(#bs.params(P), 3, "chord is the default")
  -- coincident consecutive points share a parameter, never NaN
  u = bs.params({{0, 0}, {1, 0}, {1, 0}, {2, 0}})
  T.eq(u:get(2), u:get(3)); T.near(u:get(2), 0.5)
  T.fails("EDEGENERATE", bs.params, {{1, 1}, {1, 1}, {1, 1}})
  T.raises("bad argument #2 to 'params' (invalid option 'arc')", function() bs.params(P, "arc") end)
  T.raises("bad argument #3 to 'params' (unknown option 'close')", function() bs.params(P, "chord", {close = true}) end)
end)

T.test("knots.averaging follows NURBS Book eq. 9.68-9.69", function()
  local m, n, p = 11, 6, 3
  local u = grid(m)
  local K = bs.knots.averaging{params = u, count = n, degree = p}
  local U = K:values()
  T.eq(#U, n + p + 1)
  for i = 1, p + 1 do T.eq(U[i], 0); T.eq(U[#U - i + 1], 1) end
  local d = m / (n - p) -- the book's (m+1)/(n-p+1) with m+1 points and n+1 control points
  for j = 1, n - p - 1 do
    local i = math.floor(j * d)
    local alpha = j * d - i
    -- 0-based: u_{p+j} = (1-alpha) ubar_{i-1} + alpha ubar_i
    T.near(U[p + j + 1], (1 - alpha) * u:get(i) + alpha * u:get(i + 1), 1e-14, "interior knot " .. j)
  end
  local Kc = bs.knots.averaging{params = grid(20, true), count = 8, degree = 3, closed = true}
  T.eq(#Kc, 8 + 2 * 3 + 1, "closed: expanded periodic vector")
  local a, b = Kc:domain()
  T.near(b - a, 1, 1e-14, "one period")
  T.raises("bad argument #1 to 'averaging' (rule 'averaging' is for open curves)",
           function() bs.knots.averaging{params = u, count = 6, closed = true, rule = "averaging"} end)
end)

T.test("an open fit reproduces a spline sampled from the same space", function()
  local K = bs.knots.new{degree = 3, values = {0, 0, 0, 0, 0.2, 0.45, 0.7, 1, 1, 1, 1}}
  local C0 = bs.curve.new{degree = 3, knots = K,
                          control_points = {{0, 0}, {1, 2}, {2, 3}, {4, 3}, {5, 1}, {6, -1}, {8, 0}}}
  local u = grid(200)
  local P = C0:eval_many(u)
  local F = bs.fitter{degree = 3, knots = K}
  T.eq(F:count(), 7); T.eq(F:degree(), 3); T.eq(F:is_periodic(), false)
  local C, rep = F:fit(P, u)
  control_near(C:control_points(), C0:control_points(), 1e-9, "control points")
  T.ok(rep.max < 1e-9 and rep.rms < 1e-9, "residuals vanish")
  T.ok(rep.rcond > 0 and rep.rcond <= 1, "rcond in (0, 1]")
  T.eq(rep.m, 200); T.eq(#rep.residuals, 200)
  -- weights do not change an exact reproduction
  local w = bs.vector.new(200, 1); w:set(7, 50)
  local Cw = F:fit(P, u, w)
  control_near(Cw:control_points(), C0:control_points(), 1e-9, "weighted")
  T.eq(F:knots():values()[5], 0.2, "knots of the last fit")
end)

T.test("a periodic fit reproduces a closed spline, seam included", function()
  local Q = {{0, 0}, {2, -1}, {4, 0}, {5, 2}, {3, 4}, {0, 3}}
  local C0 = bs.curve.new{degree = 3, periodic = true, control_points = Q}
  local u = grid(120, true)
  local P = C0:eval_many(u)
  local F = bs.fitter{degree = 3, periodic = true, knots = C0:knots()}
  T.eq(F:count(), 6)
  local C, rep = F:fit(P, u)
  T.ok(C:is_periodic()); T.eq(C:distinct(), 6)
  control_near(C:control_points(), C0:control_points(), 1e-9, "periodic control points")
  T.ok(rep.max < 1e-9, "residual " .. rep.max)
  -- rule-based knots on chord parameters (the default u) also give a closed curve
  local F2 = bs.fitter{degree = 3, periodic = true, count = 6}
  local C2 = F2:fit(P)
  local x0, y0 = C2:eval(C2:domain())
  local _, b = C2:domain()
  local x1, y1 = C2:eval(b)
  T.near(x0, x1, 1e-12); T.near(y0, y1, 1e-12)
end)

-- The normal equations say the weighted residual is orthogonal to every basis
-- function: sum_k w_k N_i(u_k) (Q_k - C(u_k)) = 0. N_i is evaluated as the 1-D spline
-- whose i-th control value is 1 and the others 0.
T.test("least squares: weighted residuals are orthogonal to each basis function", function()
  local m = 60
  local P = bs.points.new(m, 2)
  for k = 1, m do
    local t = (k - 1) / (m - 1)
    P:set(k, t, math.sin(6 * t) + 0.05 * math.cos(37 * k))
  end
  local u = bs.params(P, "chord")
  local w = bs.vector.new(m)
  for k = 1, m do w:set(k, 1 + (k % 3)) end
  local n = 9
  local F = bs.fitter{degree = 3, count = n}
  local C, rep = F:fit(P, u, w)
  local E = C:eval_many(u)
  local U = F:knots()
  -- report agrees with its definitions
  local sw, swr2, rmax, imax = 0, 0, -1, 0
  for k = 1, m do
    local qx, qy = P:get(k)
    local cx, cy = E:get(k)
    local r = math.sqrt((qx - cx) ^ 2 + (qy - cy) ^ 2)
    T.near(rep.residuals:get(k), r, 1e-12, "residual " .. k)
    sw = sw + w:get(k); swr2 = swr2 + w:get(k) * r * r
    if r > rmax then rmax, imax = r, k end
  end
  T.near(rep.rms, math.sqrt(swr2 / sw), 1e-12, "rms")
  T.near(rep.max, rmax, 1e-14, "max"); T.eq(rep.max_index, imax, "max_index")
  for i = 1, n do
    local e = {}
    for j = 1, n do e[j] = {j == i and 1 or 0} end
    local B = bs.curve.new{degree = 3, knots = U, control_points = e}
    local Nv = B:eval_many(u)
    local gx, gy, scale = 0, 0, 0
    for k = 1, m do
      local Ni = Nv:get(k)
      local qx, qy = P:get(k)
      local cx, cy = E:get(k)
      gx = gx + w:get(k) * Ni * (qx - cx)
      gy = gy + w:get(k) * Ni * (qy - cy)
      scale = scale + w:get(k) * Ni
    end
    T.ok(math.abs(gx) < 1e-12 * scale + 1e-13 and math.abs(gy) < 1e-12 * scale + 1e-13,
         string.format("basis %d: %g %g", i, gx, gy))
  end
end)

T.test("F:fit writes the residuals into a caller's Vector when given one", function()
  local m = 40
  local P = bs.points.new(m, 2)
  for k = 1, m do local a = 2 * math.pi * k / m; P:set(k, math.cos(a) + 0.01 * math.sin(7 * k), math.sin(a)) end
  local u = bs.params(P, "chord")
  local F = bs.fitter{degree = 3, count = 8}
  local _, fresh = F:fit(P, u)
  local r = bs.vector.new(m, -1)
  local _, rep = F:fit(P, u, nil, r)
  T.ok(rawequal(rep.residuals, r), "report.residuals is the caller's Vector")
  for k = 1, m do T.eq(r:get(k), fresh.residuals:get(k), "residual " .. k) end
  T.raises("bad argument #4 to 'fit' (39 residual slots for 40 points)",
           function() F:fit(P, u, nil, bs.vector.new(m - 1)) end)
  T.raises("bad argument #4 to 'fit' (the residuals Vector must not be the parameters or the weights)",
           function() F:fit(P, u, nil, u) end)
  T.raises({ match = "bad argument #4 to 'fit' %(bsfit.Vector expected" }, function() F:fit(P, u, nil, {}) end)
end)

T.test("solver = 'qr' | 'auto' solve the same problem; the report names the solver used", function()
  local m = 60
  local P = bs.points.new(m, 2)
  for k = 1, m do local a = 2 * math.pi * k / m; P:set(k, 2 * math.cos(a) + 0.01 * math.sin(5 * k), math.sin(a)) end
  local u = bs.params(P, "chord", {closed = true})
  for _, periodic in ipairs{false, true} do
    local C1, r1 = bs.fitter{count = 12, periodic = periodic}:fit(P, u)
    local C2, r2 = bs.fitter{count = 12, periodic = periodic, solver = "qr"}:fit(P, u)
    local C3, r3 = bs.fitter{count = 12, periodic = periodic, solver = "auto"}:fit(P, u)
    T.eq(r1.solver, "cholesky"); T.eq(r2.solver, "qr"); T.eq(r3.solver, "cholesky", "well conditioned")
    local A, B = C1:control_points(), C2:control_points()
    for i = 1, #A do
      local ax, ay = A:get(i)
      local bx, by = B:get(i)
      T.near(ax, bx, 1e-11, "x" .. i); T.near(ay, by, 1e-11, "y" .. i)
    end
    T.near(r1.rms, r2.rms, 1e-13)
    T.ok(C3)
  end
  T.raises("bad argument #1 to 'fitter' (field 'solver': invalid option 'lu')",
           function() bs.fitter{count = 5, solver = "lu"} end)
end)

T.test("a knot span without data gives nil, message, 'EEMPTYSPAN'", function()
  local K = bs.knots.clamped{degree = 3, count = 8}
  local F = bs.fitter{degree = 3, knots = K}
  local m = 40
  local P, u = bs.points.new(m, 2), bs.vector.new(m)
  for k = 1, m do
    local t = 0.5 * (k - 1) / (m - 1) -- nothing in (0.5, 1]
    u:set(k, t); P:set(k, t, t * t)
  end
  local msg = T.fails("EEMPTYSPAN", F.fit, F, P, u)
  T.ok(#msg > 0)
  local C, err, code = F:fit(P, u)
  T.ok(not C and code == "EEMPTYSPAN", "the strategy idiom: if not C then ... end")
end)

T.test("<close> and collectgarbage release fitters; a closed fitter raises", function()
  local F2
  do
    local F <close> = bs.fitter{degree = 2, count = 4}
    F2 = F
    T.eq(F:is_closed(), false)
  end
  T.eq(F2:is_closed(), true)
  T.raises("attempt to use a closed fitter", function() F2:fit({{0, 0}, {1, 1}, {2, 0}, {3, 1}}) end)
  T.eq(tostring(F2), "bsfit.Fitter (closed)")
  F2:close(); F2:close() -- idempotent
  local weak = setmetatable({}, {__mode = "v"})
  weak[1] = bs.fitter{degree = 3, count = 10}
  T.ok(tostring(weak[1]):match("^bsfit%.Fitter%(deg=3, n=10%): "))
  collectgarbage(); collectgarbage()
  T.eq(weak[1], nil, "collected")
  -- many fitters in a loop do not accumulate
  for _ = 1, 200 do local _ = bs.fitter{degree = 3, count = 50} end
  collectgarbage()
  local kb = collectgarbage("count")
  for _ = 1, 200 do local _ = bs.fitter{degree = 3, count = 50} end
  collectgarbage()
  T.ok(collectgarbage("count") < kb + 64, "no growth")
end)

T.test("misuse raises naming the argument or field", function()
  T.raises("bad argument #1 to 'fitter' (unknown option 'degre')", function() bs.fitter{degre = 3, count = 5} end)
  T.raises("bad argument #1 to 'fitter' (field 'count' (or 'knots') is required)", function() bs.fitter{degree = 3} end)
  T.raises("bad argument #1 to 'fitter' (field 'count' must be an integer)", function() bs.fitter{count = "x"} end)
  T.raises("bad argument #1 to 'fitter' (field 'fix_ends' must be a boolean)", function() bs.fitter{count = 5, fix_ends = 1} end)
  T.raises("bad argument #1 to 'fitter' (field 'rule': invalid option 'avg')", function() bs.fitter{count = 5, rule = "avg"} end)
  T.raises({match = "^bad argument #1 to 'fitter' %(.*degree"}, function() bs.fitter{degree = 3, count = 3} end)
  local F = bs.fitter{degree = 3, count = 5}
  local P = bs.points.new{{0, 0}, {1, 1}, {2, 0}, {3, 1}, {4, 0}, {5, 2}}
  T.raises("bad argument #2 to 'fit' (5 parameters for 6 points)", function() F:fit(P, {0, 0.2, 0.4, 0.6, 1}) end)
  T.raises("bad argument #3 to 'fit' (2 weights for 6 points)", function() F:fit(P, nil, {1, 1}) end)
  T.raises({match = "^bad argument #3 to 'fit' %(.*weight"}, function() F:fit(P, nil, {1, 1, -1, 1, 1, 1}) end)
  T.raises("bad argument #3 to 'fit' (weight 3 is 1e-310 (must be at least DBL_MIN = 2.2e-308))",
           function() F:fit(P, nil, {1, 1, 1e-310, 1, 1, 1}) end)
  T.raises({match = "^bad argument #1 to 'fit' %(.*"}, function() F:fit({{0, 0}, {1, 1}}) end)
  T.raises({match = "^bad argument #1 to 'fit' %(.*"}, function() F:fit({{0, 0}, {1, 0 / 0}, {2, 0}, {3, 1}, {4, 0}, {5, 2}}) end)
  T.raises("bad argument #1 to 'fit' (bsfit.Points expected, got string)", function() F:fit("points") end)
  T.raises("bad argument #1 to 'fit' (bsfit.Fitter expected, got bsfit.Points)", function() F.fit(P, P) end)
end)

T.test("F:fit on 1e6 points from Lua (timing printed)", function()
  local m = 1000000
  local C0 = bs.curve.new{degree = 3, periodic = true, control_points = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}, {0.5, -0.5}}}
  local u = grid(m, true)
  local t0 = os.clock()
  local P = C0:eval_many(u)
  local t1 = os.clock()
  local F = bs.fitter{degree = 3, periodic = true, knots = C0:knots()}
  local C, rep = F:fit(P, u)
  local t2 = os.clock()
  T.ok(C and rep.max < 1e-8, "reproduced")
  io.write(string.format("# eval_many 1e6: %.1f ms; fit 1e6: %.1f ms\n", (t1 - t0) * 1e3, (t2 - t1) * 1e3))
end)
