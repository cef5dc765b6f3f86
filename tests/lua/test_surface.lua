-- test_surface.lua: bsfit.Surface (src/lua/lsurface.c) against mathematics: linear
-- precision at the Greville abscissae, the Bernstein sum of a Bézier patch, a NURBS
-- cylinder (radius 1 everywhere), derivatives against finite differences, normals of a
-- plane, grid sampling, JSON / IGES files, and the error contract.
local T = require "tap"
local bs = require "bsfit"

local r2 = math.sqrt(2) / 2

-- control points at the Greville abscissae of knots U (degree p) and V (degree q),
-- with z = a x + b y + c: S(u, v) = (u, v, a u + b v + c) by linear precision
local function greville(U, p)
  local g = {}
  for i = 1, #U - p - 1 do
    local s = 0
    for k = i + 1, i + p do s = s + U[k] end
    g[i] = s / p
  end
  return g
end

local function plane_surface(a, b, c)
  local U, V = {0, 0, 0, 0, 0.2, 0.5, 0.55, 1, 1, 1, 1}, {0, 0, 0, 0.3, 0.6, 1, 1, 1}
  local gu, gv = greville(U, 3), greville(V, 2)
  local rows = {}
  for i = 1, #gu do
    rows[i] = {}
    for j = 1, #gv do rows[i][j] = {gu[i], gv[j], a * gu[i] + b * gv[j] + c} end
  end
  return bs.surface.new{degree_u = 3, degree_v = 2, knots_u = U, knots_v = V, control_points = rows}, #gu, #gv
end

-- a quarter of the unit cylinder x^2 + y^2 = 1, 0 <= z <= 2 (NURBS Book ex. 7.1 in u)
local function cylinder()
  return bs.surface.new{degree_u = 2, degree_v = 1, knots_u = {0, 0, 0, 1, 1, 1}, knots_v = {0, 0, 1, 1},
                        control_points = {{{1, 0, 0}, {1, 0, 2}}, {{1, 1, 0}, {1, 1, 2}}, {{0, 1, 0}, {0, 1, 2}}},
                        weights = {{1, 1}, {r2, r2}, {1, 1}}}
end

T.test("linear precision: Greville control points reproduce (u, v, a u + b v + c)", function()
  local S, nu, nv = plane_surface(0.5, -2, 3)
  T.eq(S:kind(), "bspline"); T.eq(S:dim(), 3)
  local cu, cv = S:count()
  T.eq(cu, nu); T.eq(cv, nv)
  local pu, pv = S:degree()
  T.eq(pu, 3); T.eq(pv, 2)
  local u0, u1, v0, v1 = S:domain()
  T.eq(u0, 0); T.eq(u1, 1); T.eq(v0, 0); T.eq(v1, 1)
  for i = 0, 10 do
    for j = 0, 10 do
      local u, v = i / 10, j / 10
      local x, y, z = S:eval(u, v)
      T.near(x, u, 1e-14); T.near(y, v, 1e-14); T.near(z, 0.5 * u - 2 * v + 3, 1e-14)
    end
  end
end)

T.test("Bezier patch: the Bernstein double sum, computed by hand", function()
  local rows = {}
  for i = 1, 4 do
    rows[i] = {}
    for j = 1, 3 do rows[i][j] = {i, j, (i * j) % 5 - 1} end
  end
  local B = bs.bezier_surface.new{control_points = rows}
  T.eq(B:kind(), "bezier")
  local pu, pv = B:degree()
  T.eq(pu, 3); T.eq(pv, 2)
  local function bern(n, k, t)
    local c = 1
    for r = 1, k do c = c * (n - r + 1) / r end
    return c * t ^ k * (1 - t) ^ (n - k)
  end
  for _, uv in ipairs{{0, 0}, {0.3, 0.8}, {0.5, 0.5}, {1, 0.25}} do
    local want = {0, 0, 0}
    for i = 1, 4 do
      for j = 1, 3 do
        local w = bern(3, i - 1, uv[1]) * bern(2, j - 1, uv[2])
        for k = 1, 3 do want[k] = want[k] + w * rows[i][j][k] end
      end
    end
    local got = {B:eval(uv[1], uv[2])}
    for k = 1, 3 do T.near(got[k], want[k], 1e-14, "coord " .. k) end
  end
end)

T.test("NURBS cylinder: radius 1 and z = 2 v everywhere; normal radial", function()
  local S = cylinder()
  T.eq(S:kind(), "nurbs"); T.ok(S:is_rational())
  for i = 0, 8 do
    for j = 0, 4 do
      local x, y, z = S:eval(i / 8, j / 4)
      T.near(x * x + y * y, 1, 1e-14); T.near(z, 2 * j / 4, 1e-14)
      local nx, ny, nz = S:normal(i / 8, j / 4)
      T.near(nx * nx + ny * ny + nz * nz, 1, 1e-14, "unit")
      T.near(math.abs(nx * x + ny * y), 1, 1e-12, "radial"); T.near(nz, 0, 1e-14)
    end
  end
  local w = S:weights()
  T.eq(#w, 6); T.near(w:get(3), r2)
end)

T.test("deriv agrees with finite differences (polynomial and rational)", function()
  local h = 1e-5
  local P = bs.surface.new{degree_u = 3, degree_v = 2, control_points = (function()
    local rows = {}
    for i = 1, 5 do
      rows[i] = {}
      for j = 1, 4 do rows[i][j] = {i + 0.1 * j * j, j - 0.2 * i, math.sin(i + j)} end
    end
    return rows
  end)(), knots_u = {0, 0, 0, 0, 0.4, 1, 1, 1, 1}, knots_v = {0, 0, 0, 0.5, 1, 1, 1}}
  for _, S in ipairs{P, cylinder()} do
    for _, uv in ipairs{{0.2, 0.3}, {0.7, 0.6}} do
      local u, v = uv[1], uv[2]
      local xu = {S:eval(u + h, v)}
      local xd = {S:eval(u - h, v)}
      local yu = {S:eval(u, v + h)}
      local yd = {S:eval(u, v - h)}
      local pp, pm, mp, mm = {S:eval(u + h, v + h)}, {S:eval(u + h, v - h)}, {S:eval(u - h, v + h)}, {S:eval(u - h, v - h)}
      local Su, Sv, Suv, S0 = {S:deriv(u, v, 1, 0)}, {S:deriv(u, v, 0, 1)}, {S:deriv(u, v, 1, 1)}, {S:deriv(u, v, 0, 0)}
      local E = {S:eval(u, v)}
      for k = 1, 3 do
        T.near(Su[k], (xu[k] - xd[k]) / (2 * h), 1e-6, "S_u")
        T.near(Sv[k], (yu[k] - yd[k]) / (2 * h), 1e-6, "S_v")
        T.near(Suv[k], (pp[k] - pm[k] - mp[k] + mm[k]) / (4 * h * h), 1e-4, "S_uv")
        T.near(S0[k], E[k], 1e-14, "order 0")
      end
    end
  end
  -- above the degree in one direction a polynomial surface's derivative is 0
  local z = {P:deriv(0.3, 0.3, 4, 0)}
  for k = 1, 3 do T.eq(z[k], 0) end
end)

T.test("normal of a plane is (-a, -b, 1) / |.|; sample equals eval on the grid", function()
  local S = plane_surface(0.5, -2, 3)
  local n = math.sqrt(0.25 + 4 + 1)
  local nx, ny, nz = S:normal(0.37, 0.81)
  T.near(nx, -0.5 / n, 1e-14); T.near(ny, 2 / n, 1e-14); T.near(nz, 1 / n, 1e-14)
  local G = S:sample(5, 4)
  T.eq(#G, 20); T.eq(G:dim(), 3)
  for a = 0, 4 do
    for b = 0, 3 do
      local x, y, z = G:get(a * 4 + b + 1)
      local ex, ey, ez = S:eval(a / 4, b / 3)
      T.near(x, ex, 1e-14); T.near(y, ey, 1e-14); T.near(z, ez, 1e-14)
    end
  end
  -- a collapsed edge (a pole): the partial derivatives are parallel, the fail triple
  local pole = bs.bezier_surface.new{control_points = {{{0, 0, 1}, {0, 0, 1}}, {{1, 0, 0}, {0, 1, 0}}}}
  T.fails("EDEGENERATE", pole.normal, pole, 0, 0.5)
end)

T.test("accessors, copies, JSON round trip, files", function()
  local S = cylinder()
  T.eq(getmetatable(S:knots_u()).__name, "bsfit.Knots"); T.eq(#S:knots_u(), 6); T.eq(S:knots_v():degree(), 1)
  local P = S:control_points()
  T.eq(#P, 6)
  local x, y, z = P:get(4) -- point (2, 2)
  T.eq(x, 1); T.eq(y, 1); T.eq(z, 2)
  local s = S:to_json()
  T.ok(s:find('"type"%s*:%s*"nurbs_surface"'), s)
  local R = bs.surface.from_json(s)
  T.eq(R:control_points():bytes(), P:bytes()); T.eq(R:weights():bytes(), S:weights():bytes())
  T.eq(R:to_json(), s)
  local D = S:copy()
  T.eq(D:to_json(), s)
  T.fails("EFORMAT", bs.surface.from_json, '{"type": "bspline_surface"')
  local base = os.tmpname()
  T.eq(S:write(base .. ".json"), S)
  local f = assert(io.open(base .. ".json"))
  T.eq(f:read("a"), s); f:close()
  T.eq(S:write(base .. ".iges"), S)
  local de = 0
  for line in io.lines(base .. ".iges") do
    T.eq(#line, 80, "IGES fixed 80-column records")
    if line:sub(73, 73) == "D" and line:sub(1, 8) == "     128" then de = de + 1 end
  end
  T.eq(de, 2, "one entity 128: two directory-entry lines")
  os.remove(base .. ".json"); os.remove(base .. ".iges"); os.remove(base)
  T.fails("EIO", S.write, S, "/nonexistent/dir/s.json")
end)

T.test("close / <close> release; later use raises; __gc idempotent", function()
  local S = cylinder()
  do
    local E <close> = S:copy()
    T.ok(E:eval(0.5, 0.5))
    S = E
  end
  T.raises("attempt to use a closed surface", function() S:eval(0.5, 0.5) end)
  T.eq(tostring(S), "bsfit.Surface (closed)")
  S:close(); S:close()
  T.ok(tostring(cylinder()):match("^bsfit%.Surface%(deg=2x1, n=3x2, dim=3%): "))
  collectgarbage(); collectgarbage()
end)

T.test("misuse raises with the argument named", function()
  local S = cylinder()
  local net = {{{0, 0, 0}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 1}}}
  T.raises("bad argument #1 to 'new' (field 'degree_u' is required)",
           function() bs.surface.new{degree_v = 1, control_points = net} end)
  T.raises("bad argument #1 to 'new' (unknown option 'degree')",
           function() bs.surface.new{degree = 1, degree_u = 1, degree_v = 1, control_points = net} end)
  T.raises("bad argument #1 to 'new' (field 'control_points' is required)",
           function() bs.surface.new{degree_u = 1, degree_v = 1} end)
  T.raises("bad argument #1 to 'new' (field 'control_points': row 2 has 1 entries, expected 2)",
           function() bs.surface.new{degree_u = 1, degree_v = 1, control_points = {net[1], {{1, 0, 0}}}} end)
  T.raises("bad argument #1 to 'new' (field 'control_points': point (2, 1) has 2 coordinates)",
           function() bs.surface.new{degree_u = 1, degree_v = 1, control_points = {net[1], {{1, 0}, {1, 1}}}} end)
  T.raises("bad argument #1 to 'new' (field 'control_points': point (1, 2) has a non-finite coordinate)",
           function() bs.surface.new{degree_u = 1, degree_v = 1, control_points = {{{0, 0, 0}, {0 / 0, 1, 0}}, net[2]}} end)
  T.raises("bad argument #1 to 'new' (degrees (2, 1) need at least 3 x 2 control points, got 2 x 2)",
           function() bs.surface.new{degree_u = 2, degree_v = 1, control_points = net} end)
  T.raises("bad argument #1 to 'new' (degree 1 with 2 control points in v needs 4 knots, got 3)",
           function() bs.surface.new{degree_u = 1, degree_v = 1, control_points = net, knots_v = {0, 0, 1}} end)
  T.raises("bad argument #1 to 'new' (field 'weights': weight (2, 1) is -1 (must be positive and finite))",
           function() bs.surface.new{degree_u = 1, degree_v = 1, control_points = net, weights = {{1, 1}, {-1, 1}}} end)
  T.raises({match = "^bad argument #1 to 'new' %(.*decreas"},
           function() bs.surface.new{degree_u = 1, degree_v = 1, control_points = net, knots_u = {0, 0, 1, 0.5}} end)
  T.raises("bad argument #2 to 'eval' (number expected, got no value)", function() S:eval(0.5) end)
  T.raises({match = "^bad argument #1 to 'eval' %(parameter .* is not finite%)$"}, function() S:eval(0 / 0, 0.5) end)
  T.raises("bad argument #3 to 'deriv' (derivative order out of range 0..30)", function() S:deriv(0.5, 0.5, -1, 0) end)
  T.raises("bad argument #2 to 'sample' (count 1 out of range 2..9223372036854775807)", function() S:sample(5, 1) end)
  T.raises("bad argument #1 to 'write' (file name must end in .json, .iges, .igs, .step, .stp or .obj)", function() S:write("s.txt") end)
  local flat = bs.surface.new{degree_u = 1, degree_v = 1, control_points = {{{0, 0}, {0, 1}}, {{1, 0}, {1, 1}}}}
  T.raises({match = "normal"}, function() flat:normal(0.5, 0.5) end)
  T.raises("bad argument #1 to 'eval' (bsfit.Surface expected, got bsfit.Curve)",
           function() S.eval(bs.bezier.new{control_points = {{0, 0}, {1, 1}}}, 0, 0) end)
end)
