-- test_errors.lua: the error contract of the binding (STYLE R3, R6): misuse raises
-- `bad argument #N to 'f' (...)`, numerical outcomes return nil, message, code name.
local T = require "tap"
local bs = require "bsfit"

T.test("module: version fields, metatable names, no globals", function()
  T.ok(bs.version:match("^%d+%.%d+%.%d+$"), bs.version)
  T.eq(bs._VERSION, "bsfit " .. bs.version)
  T.eq(rawget(_G, "bsfit"), nil, "require sets no global")
  local names = {
    [bs.points.new(1, 2)] = "bsfit.Points", [bs.vector.new(1)] = "bsfit.Vector",
    [bs.knots.clamped{degree = 1, count = 2}] = "bsfit.Knots",
    [bs.bezier.new{control_points = {{0, 0}, {1, 1}}}] = "bsfit.Curve",
    [bs.fitter{degree = 1, count = 2}] = "bsfit.Fitter",
    [bs.bezier_surface.new{control_points = {{{0, 0, 0}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 1}}}}] = "bsfit.Surface",
    [bs.svg.new{0, 0, 1, 1}] = "bsfit.Svg"}
  for obj, name in pairs(names) do
    T.eq(getmetatable(obj).__name, name)
    T.ok(tostring(obj):sub(1, #name) == name, tostring(obj))
  end
  T.eq(bs.errname(-20), "ESINGULAR"); T.eq(bs.errname(-24), "EEMPTYSPAN")
end)

T.test("wrong userdata types name the expected type", function()
  local P = bs.points.new{{0, 0}}
  local C = bs.bezier.new{control_points = {{0, 0}, {1, 1}}}
  local v = bs.vector.new{1}
  T.raises("bad argument #1 to 'eval' (bsfit.Curve expected, got bsfit.Points)", function() C.eval(P, 0) end)
  T.raises("bad argument #1 to 'degree' (bsfit.Knots expected, got bsfit.Curve)",
           function() bs.knots.clamped{degree = 1, count = 2}.degree(C) end)
  T.raises("bad argument #1 to 'eval_many' (bsfit.Vector expected, got bsfit.Points)", function() C:eval_many(P) end)
  T.raises("bad argument #1 to 'get' (bsfit.Vector expected, got nil)", function() v.get(nil, 1) end)
  local impostor = {eval = C.eval}
  T.raises("calling 'eval' on bad self (bsfit.Curve expected, got table)", function() impostor:eval(0) end)
end)

T.test("option tables: unknown names, wrong field types, required fields", function()
  T.raises("bad argument #1 to 'new' (unknown option 'weight')",
           function() bs.curve.new{degree = 1, control_points = {{0, 0}, {1, 1}}, weight = {1, 1}} end)
  T.raises("bad argument #1 to 'new' (option names must be strings, got number)",
           function() bs.curve.new{degree = 1, control_points = {{0, 0}, {1, 1}}, 5} end)
  T.raises("bad argument #1 to 'new' (field 'degree' must be an integer)",
           function() bs.curve.new{degree = 1.5, control_points = {{0, 0}, {1, 1}}} end)
  T.raises("bad argument #1 to 'new' (field 'control_points' must be a table or bsfit.Points)",
           function() bs.curve.new{degree = 1, control_points = 7} end)
  T.raises("bad argument #1 to 'new' (field 'degree' is required)",
           function() bs.curve.new{control_points = {{0, 0}, {1, 1}}} end)
  T.raises("bad argument #1 to 'new' (table expected, got no value)", function() bs.curve.new() end)
  T.raises("bad argument #1 to 'averaging' (field 'count' is required)",
           function() bs.knots.averaging{params = {0, 1}} end)
end)

T.test("NaN and non-monotone knots are misuse", function()
  local C = bs.bezier.new{control_points = {{0, 0}, {1, 1}}}
  T.raises("bad argument #1 to 'eval' (parameter is not finite)", function() C:eval(0 / 0) end)
  T.raises("bad argument #1 to 'eval' (parameter is not finite)", function() C:eval(math.huge) end)
  T.raises("bad argument #1 to 'new' (knots decrease at knot 3 (0 < 1))",
           function() bs.knots.new{degree = 0, values = {0, 1, 0}} end)
  T.raises("bad argument #1 to 'new' (knots decrease at knot 3 (0 < 1))",
           function() bs.curve.new{degree = 0, knots = {0, 1, 0}, control_points = {{0, 0}, {1, 1}}} end)
end)

T.test("numerical outcomes return the fail triple", function()
  -- all points coincident: no parameters can be assigned
  local r, msg, code = bs.params({{2, 2}, {2, 2}})
  T.ok(not r); T.eq(type(msg), "string"); T.eq(code, "EDEGENERATE")
  -- a fit whose knot spans hold no data
  local F = bs.fitter{degree = 1, knots = {0, 0, 0.5, 1, 1}}
  local C, m2, c2 = F:fit({{0, 0}, {0.1, 0}, {0.2, 0}}, {0, 0.1, 0.2})
  T.ok(not C); T.ok(m2:find("span"), m2); T.eq(c2, "EEMPTYSPAN")
  -- the empty span is named as K:span numbers it, from 1 (the core counts from 0)
  local K = bs.knots.new{degree = 1, values = {0, 0, 0.5, 1, 1}}
  T.ok(m2:find("knot span " .. K:span(0.7) .. " [0.5, 1)", 1, true), m2)
  -- files
  T.fails("EIO", bs.points.read, "/nonexistent/dir/x.csv")
  T.fails("EFORMAT", bs.curve.from_json, "[1, 2")
end)

-- issue 13 (core): no wrong answer with success
T.test("exact filter: windows below the resolution are refused, never garbage", function()
  local C = bs.curve.new{degree = 3, knots = {0, 0, 0, 0, 0.25, 0.5, 0.75, 1, 1, 1, 1},
                         control_points = {{0, 0}, {1, 2}, {2, 5}, {3, 1}, {4, 0}, {5, 3}, {1, 1}}}
  for _, d in ipairs{1e-15, 1e-12, 1e-9} do
    T.raises({match = "below the exact filter's resolution"}, function() bs.filter.box(C, {delta = d}) end)
  end
  local F = bs.filter.box(C, {delta = 1e-6})
  for i = 1, 9 do -- a window that narrow leaves the curve as it was, to its curvature * 1e-12
    local x0, y0 = C:eval(i / 10)
    local x1, y1 = F:eval(i / 10)
    T.near(x1, x0, 1e-8); T.near(y1, y0, 1e-8)
  end
end)

T.test("closed curves with a knot of multiplicity degree + 1 are refused", function()
  T.raises({match = "multiplicity 2 > degree 1"}, function()
    bs.curve.new{degree = 1, periodic = true, knots = {0, 1, 1}, control_points = {{0, 0}, {1, 0}}}
  end)
end)

T.test("chord parameters of points 1e-300 apart are finite", function()
  local u = bs.params(bs.points.new{{1e-300, 0}, {0, 0}, {0, 0}}, "chord")
  T.eq(u:get(1), 0); T.eq(u:get(2), 1); T.eq(u:get(3), 1)
  u = bs.params(bs.points.new{{1e-300, 0}, {0, 0}, {1e-300, 1e-300}}, "centripetal")
  T.eq(u:get(1), 0); T.ok(u:get(2) > 0 and u:get(2) < 1); T.eq(u:get(3), 1)
end)

T.test("coordinates, weights and tangents beyond the documented range", function()
  T.raises({match = "^bad argument #1 to '[%w.]*params' %(point 2 has a coordinate 1e%+200 beyond 1e100%)$"},
           function() bs.params(bs.points.new{{0, 0}, {1e200, 0}, {0, 1}}, "chord") end)
  T.raises({match = "weight 1 is 1e%-310 %(must be in %[1e%-100, 1e100%]%)"}, function()
    bs.curve.new{degree = 2, knots = {0, 0, 0, 1, 1, 1}, weights = {1, 1e-310, 1},
                 control_points = {{0, 0}, {1, 0}, {0, 1}}}
  end)
  T.raises({match = "beyond 1e100"}, function()
    bs.curve.new{degree = 2, knots = {0, 0, 0, 1, 1, 1}, control_points = {{0, 0}, {1e300, 0}, {0, 1}}}
  end)
  local R = bs.curve.new{degree = 1, knots = {0, 0, 2e-99, 1, 1}, control_points = {{0, 0}, {1, 0}, {0, 1}}}
  T.raises({match = "^reverse: the result would be invalid"}, function() R:reverse() end)
end)

T.test("the moving average of a minimal closed curve is refused", function()
  local P = bs.curve.new{degree = 2, periodic = true, control_points = {{0, 0}, {1, 0}, {0, 1}}}
  T.raises({match = "needs 4 distinct control points; this one has 3"},
           function() bs.filter.box(P, 2) end)
end)
