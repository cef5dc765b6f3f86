-- test_curve_ops.lua: the curve operations of src/bsfit_curve_ops.h through bsfit.Curve
-- (sample, split, reverse, elevate, length, closest, project, deriv of any order) and
-- C:write by extension, checked against mathematics: the unit quarter circle (NURBS
-- Book ex. 7.1: length pi/2, radial feet), identities of the operations
-- (split pieces, reversal and elevation describe the same points), finite differences.
local T = require "tap"
local bs = require "bsfit"

local r2 = math.sqrt(2) / 2
local pi = math.pi

local function quarter_circle()
  return bs.curve.new{degree = 2, knots = {0, 0, 0, 1, 1, 1},
                      control_points = {{1, 0}, {1, 1}, {0, 1}}, weights = {1, r2, 1}}
end

local function wavy()
  return bs.curve.new{degree = 3, knots = {0, 0, 0, 0, 0.2, 0.45, 0.7, 1, 1, 1, 1},
                      control_points = {{0, 0}, {1, 2}, {2, -1}, {3, 3}, {4, 0}, {5, 1}, {6, 2}}}
end

local function closed()
  return bs.curve.new{degree = 3, periodic = true, control_points = {{0, 0}, {2, -1}, {3, 1}, {2, 3}, {-1, 2}}}
end

-- |A(s) - B(f(s))| small for s in [lo, hi]
local function same_points(A, B, lo, hi, f, tol, what)
  for i = 0, 20 do
    local s = lo + (hi - lo) * i / 20
    local ax, ay = A:eval(s)
    local bx, by = B:eval(f and f(s) or s)
    T.near(ax, bx, tol, what .. " x at " .. s); T.near(ay, by, tol, what .. " y at " .. s)
  end
end

T.test("sample: K points equally spaced in parameter; periodic curves leave out C(b)", function()
  local C = wavy()
  local S = C:sample(11)
  T.eq(#S, 11); T.eq(S:dim(), 2)
  for i = 1, 11 do
    local x, y = S:get(i)
    local ex, ey = C:eval((i - 1) / 10)
    T.near(x, ex, 1e-14); T.near(y, ey, 1e-14)
  end
  T.eq(#C:sample(), 1000, "default 1000 samples")
  local P = closed()
  local Q = P:sample(10)
  for i = 1, 10 do
    local x, y = Q:get(i)
    local ex, ey = P:eval((i - 1) / 10)
    T.near(x, ex, 1e-14); T.near(y, ey, 1e-14)
  end
  T.raises("bad argument #1 to 'sample' (count 1 out of range 2..9223372036854775807)", function() C:sample(1) end)
end)

T.test("split: the two pieces are the curve on [a, t] and [t, b]; a closed curve opens", function()
  for _, C in ipairs{wavy(), quarter_circle()} do
    local L, R = C:split(0.3)
    local la, lb = L:domain()
    local ra, rb = R:domain()
    T.eq(la, 0); T.near(lb, 0.3, 1e-15); T.near(ra, 0.3, 1e-15); T.eq(rb, 1)
    same_points(L, C, 0, 0.3, nil, 1e-13, "left")
    same_points(R, C, 0.3, 1, nil, 1e-13, "right")
    T.eq(L:is_rational(), C:is_rational())
  end
  local P = closed()
  local O, none = P:split(0.25)
  T.eq(none, nil); T.ok(not O:is_periodic())
  local a, b = O:domain()
  T.near(a, 0.25, 1e-15); T.near(b, 1.25, 1e-15)
  same_points(O, P, 0.25, 1.25, nil, 1e-13, "opened")
  T.raises({match = "^bad argument #1 to 'split' %("}, function() wavy():split(1) end)
end)

T.test("reverse: R(t) = C(a + b - t); elevate keeps the points and raises the degree", function()
  for _, C in ipairs{wavy(), quarter_circle(), closed()} do
    local a, b = C:domain()
    local R = C:reverse()
    T.eq(R:degree(), C:degree()); T.eq(R:is_periodic(), C:is_periodic())
    same_points(R, C, a, b, function(s) return a + b - s end, 1e-13, "reversed")
    local E1, E2 = C:elevate(), C:elevate(2)
    T.eq(E1:degree(), C:degree() + 1); T.eq(E2:degree(), C:degree() + 2)
    same_points(E1, C, a, b, nil, 1e-12, "elevated once")
    same_points(E2, C, a, b, nil, 1e-12, "elevated twice")
  end
  T.eq(wavy():elevate(0):degree(), 3)
  T.raises("bad argument #1 to 'elevate' (elevation out of range 0..27 (degree 3, at most 30))",
           function() wavy():elevate(28) end)
end)

T.test("length: a quarter of the unit circle is pi/2; a part is its angle", function()
  local C = quarter_circle()
  T.near(C:length(), pi / 2, 1e-12)
  for _, ab in ipairs{{0, 0.5}, {0.2, 0.9}, {0.5, 0.5}} do
    local x0, y0 = C:eval(ab[1])
    local x1, y1 = C:eval(ab[2])
    T.near(C:length(ab[1], ab[2]), math.atan(y1, x1) - math.atan(y0, x0), 1e-12)
  end
  local seg = bs.curve.new{degree = 1, control_points = {{0, 0}, {3, 4}}}
  T.near(seg:length(), 5, 1e-14)
  T.raises({match = "^bad argument #2 to 'length' %("}, function() C:length(0.5, 2) end)
  T.raises({match = "^bad argument #2 to 'length' %("}, function() C:length(0.8, 0.2) end)
end)

T.test("closest: the foot on a circle is radial; project slides many points to their feet", function()
  local C = quarter_circle()
  local t, d = C:closest(2, 2)
  T.near(t, 0.5, 1e-10); T.near(d, 2 * math.sqrt(2) - 1, 1e-12)
  local x, y = C:eval(t)
  T.near(x, r2, 1e-12); T.near(y, r2, 1e-12)
  -- points off the circle by r - 1 along the radius at angle th_i
  local pts, u0, want, rad = {}, {}, {}, {}
  for i = 1, 9 do
    local th = pi / 2 * i / 10
    local r = 1 + 0.1 * math.sin(i)
    pts[i] = {r * math.cos(th), r * math.sin(th)}
    local ft = C:closest(pts[i][1], pts[i][2])
    want[i], rad[i] = ft, math.abs(r - 1)
    u0[i] = math.min(1, math.max(0, ft + 0.05 * math.cos(3 * i))) -- a nearby start
  end
  local U0 = bs.vector.new(u0)
  local u, dist = C:project(pts, U0)
  T.eq(getmetatable(u).__name, "bsfit.Vector"); T.eq(#u, 9); T.eq(#dist, 9)
  for i = 1, 9 do
    T.near(u:get(i), want[i], 1e-9, "foot " .. i)
    T.near(dist:get(i), rad[i], 1e-12, "distance " .. i)
    local fx, fy = C:eval(u:get(i))
    T.near(math.atan(fy, fx), pi / 2 * i / 10, 1e-9, "foot angle " .. i)
  end
  T.eq(U0:get(1), u0[1], "u0 unchanged")
  T.raises("bad argument #2 to 'project' (2 parameters for 9 points)", function() C:project(pts, {0, 1}) end)
  T.raises("bad argument #2 to 'project' (parameter 2 is not finite)",
           function() C:project({{0, 0}, {1, 1}}, {0, 0 / 0}) end)
  T.raises("bad argument #1 to 'project' (point 2 has a non-finite coordinate)",
           function() C:project({{0, 0}, {1, 0 / 0}}, {0, 0}) end)
  T.raises("bad argument #1 to 'project' (points of dimension 3 for a curve of dimension 2)",
           function() C:project({{0, 0, 0}}, {0}) end)
  T.raises("bad argument #3 to 'closest' (too many coordinates (curve has 2))", function() C:closest(1, 2, 3) end)
  T.raises("bad argument #2 to 'closest' (coordinate is not finite)", function() C:closest(1, 0 / 0) end)
end)

T.test("deriv of any order: 0 above a polynomial's degree; a rational curve's by differences", function()
  local C = wavy()
  for _, k in ipairs{4, 5, 100, 1 << 40} do
    local x, y = C:deriv(0.3, k)
    T.eq(x, 0); T.eq(y, 0)
  end
  local Q = quarter_circle()
  local h = 1e-5
  for _, k in ipairs{3, 4, 6} do
    for _, t in ipairs{0.2, 0.6} do
      local px, py = Q:deriv(t + h, k - 1)
      local mx, my = Q:deriv(t - h, k - 1)
      local dx, dy = Q:deriv(t, k)
      local scale = math.max(1, math.abs(dx), math.abs(dy))
      T.near(dx / scale, (px - mx) / (2 * h) / scale, 1e-5, "x^(" .. k .. ")")
      T.near(dy / scale, (py - my) / (2 * h) / scale, 1e-5, "y^(" .. k .. ")")
    end
  end
  T.raises("bad argument #2 to 'deriv' (derivative order of a rational curve out of range 0..1000)",
           function() Q:deriv(0.5, 1001) end)
  T.raises("bad argument #1 to 'deriv' (parameter is not finite)", function() C:deriv(0 / 0, 7) end)
end)

T.test("write by extension: json, svg, iges, csv (K samples)", function()
  local C = wavy()
  local base = os.tmpname()
  T.eq(C:write(base .. ".csv", {samples = 7}), C)
  local P = assert(bs.points.read(base .. ".csv"))
  T.eq(#P, 7)
  T.eq(P:bytes(), C:sample(7):bytes(), "the samples, bit for bit (%.17g)")
  T.eq(#assert(bs.points.read((C:write(base .. ".csv") and base .. ".csv"))), 1000, "default 1000")
  T.eq(C:write(base .. ".svg"), C)
  local f = assert(io.open(base .. ".svg"))
  local svg = f:read("a"); f:close()
  T.ok(svg:find("^<%?xml") and svg:find("</svg>%s*$"), "an SVG document")
  T.ok(svg:find('class="control"') and svg:find('class="curve"'), "control polygon and curve layers")
  T.eq(C:write(base .. ".iges"), C)
  local de = 0
  for line in io.lines(base .. ".iges") do
    if line:sub(73, 73) == "D" and line:sub(1, 8) == "     126" then de = de + 1 end
  end
  T.eq(de, 2, "one entity 126")
  T.eq(C:write(base .. ".json"), C)
  T.eq(bs.curve.read(base .. ".json"):to_json(), C:to_json())
  for _, ext in ipairs{".csv", ".svg", ".iges", ".json"} do os.remove(base .. ext) end
  os.remove(base)
  T.fails("EIO", C.write, C, "/nonexistent/dir/c.svg")
  T.raises("bad argument #2 to 'write' (unknown option 'sample')", function() C:write("x.csv", {sample = 3}) end)
  T.raises("bad argument #2 to 'write' (field 'samples' must be in 2..1e8)", function() C:write("x.csv", {samples = 1}) end)
  local line1 = bs.curve.new{degree = 1, control_points = {{0}, {1}}}
  T.raises("bad argument #1 to 'write' (a curve of dimension 1 cannot be written as .svg)",
           function() line1:write("x.svg") end)
end)

T.test("shape measures: a circle's turning 2 pi and bending 2 pi / r; deviation of a shift", function()
  -- a full circle of radius 3: four rational quarter arcs, closed
  local cp, w = {}, {}
  local corners = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}, {1, 0}}
  for i, p in ipairs(corners) do cp[i] = {3 * p[1], 3 * p[2]}; w[i] = (i % 2 == 0) and r2 or 1 end
  local C = bs.curve.new{degree = 2, knots = {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1},
                         control_points = cp, weights = w}
  -- the sampled polygon turns by the whole circle but the last chord step: 2 pi - O(1/K)
  local turn = C:total_turning(2000)
  T.ok(turn <= 2 * pi and turn > 2 * pi * (1 - 2 / 2000), "turning " .. turn)
  T.near(C:bending_energy(2000), 2 * pi / 3, 1e-2, "bending")
  local D = bs.curve.new{degree = 2, knots = C:knots(), weights = w,
                         control_points = (function()
                           local t = {}
                           for i, p in ipairs(cp) do t[i] = {p[1] + 0.3, p[2] - 0.4} end
                           return t
                         end)()}
  T.near(C:max_deviation(D), 0.5, 1e-14, "a translation by (0.3, -0.4)")
  T.near(C:max_deviation(C:elevate()), 0, 1e-13)
  T.ok(not C:is_uniform())
  T.ok(bs.curve.new{degree = 2, knots = bs.knots.uniform{degree = 2, count = 5},
                    control_points = {{0, 0}, {1, 1}, {2, 0}, {3, 1}, {4, 0}}}:is_uniform())
  T.raises("bad argument #1 to 'total_turning' (count 2 out of range 3..9223372036854775807)",
           function() C:total_turning(2) end)
  T.raises({match = "^bad argument #1 to 'max_deviation' %("},
           function() C:max_deviation(bs.curve.new{degree = 1, control_points = {{0, 0, 0}, {1, 1, 1}}}) end)
end)

T.test("C:closest_many equals C:closest point by point", function()
  local C = bs.curve.new { degree = 2, control_points = { { 1, 0 }, { 1, 1 }, { 0, 1 } },
                           weights = { 1, math.sqrt(0.5), 1 } } -- quarter circle
  local P = bs.points.new { { 2, 0.5 }, { 0.3, 0.3 }, { -1, 2 }, { 0.7, 0.7 } }
  local u, d = C:closest_many(P)
  for i = 1, #P do
    local ui, di = C:closest(P:get(i))
    T.near(d:get(i), di, 1e-12)
    T.near(u:get(i), ui, 1e-9)
  end
  -- a point on the arc's radius at distance r from the centre is |r - 1| away
  T.near(d:get(4), math.abs(math.sqrt(0.98) - 1), 1e-12)
  T.raises({ match = "point 1" }, function() C:closest_many(bs.points.new { { 0 / 0, 1 } }) end)
end)
