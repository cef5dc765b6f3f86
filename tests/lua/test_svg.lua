-- test_svg.lua: bs.svg (src/lua/lsvg.c), a picture built in layers. Checks the
-- geometry of the mapping (viewBox = data box + 5% margin, y up, width fixed by the
-- option, height by the aspect ratio), the layers and their classes, escaping,
-- ending (tostring and write both work, later layers raise), and the error contract.
local T = require "tap"
local bs = require "bsfit"

local function circle_pts(m)
  local t = {}
  for k = 0, m - 1 do t[#t + 1] = {math.cos(2 * math.pi * k / m), math.sin(2 * math.pi * k / m)} end
  return t
end

T.test("a box {xmin, ymin, xmax, ymax}: size, margin, y axis up", function()
  local doc = bs.svg.new({0, 0, 10, 5}, {width = 440})
  doc:marker(0, 0, "origin"):marker(10, 5, "far")
  local s = doc:tostring()
  -- side 10, margin 0.5 on each side: 11 x 6 data units, 40 px per unit
  T.ok(s:find('width="440.00" height="240.00"', 1, true), s:sub(1, 200))
  T.ok(s:find('<circle cx="20.000" cy="220.000"', 1, true), "(0, 0) is 0.5 unit in from the bottom left")
  T.ok(s:find('<circle cx="420.000" cy="20.000"', 1, true), "(10, 5) is 0.5 unit in from the top right")
  T.ok(s:find(">origin</text>", 1, true) and s:find(">far</text>", 1, true))
  T.eq(doc:tostring(), s, "tostring again gives the same text")
end)

T.test("layers: points, polyline, curve, control polygon; classes and escaping", function()
  local P = bs.points.new(circle_pts(12))
  local C = bs.curve.new{degree = 3, periodic = true, control_points = circle_pts(6)}
  local doc = bs.svg.new(P)
  T.eq(doc:points(P, "data", 3), doc, "layers chain")
  doc:polyline({{-1, -1}, {1, 1}}, {class = "diag"})
  doc:polyline(P, {closed = true})
  doc:curve(C, {samples = 50, class = "fit"})
  doc:control_polygon(C)
  doc:marker(0, 0, "a<b & \"c\"", "start")
  local s = doc:tostring()
  local _, ncircle = s:gsub('<circle [^>]*r="3"/>', "")
  T.eq(ncircle, 12, "one circle of radius 3 per point")
  T.ok(s:find('<g class="data">', 1, true))
  T.ok(s:find('<polyline class="diag"', 1, true))
  T.ok(s:find('<polygon class="curve"', 1, true), "closed polyline is a polygon")
  T.ok(s:find('<polygon class="fit"', 1, true), "a periodic curve is drawn closed")
  T.ok(s:find('<polygon class="control"', 1, true))
  T.ok(s:find("a&lt;b &amp; &quot;c&quot;", 1, true), "label escaped")
  local fit = s:match('<polygon class="fit" fill="none" points="([^"]*)"')
  local _, n = fit:gsub("[%d.]+,[%d.]+", "")
  T.eq(n, 50, "50 samples")
  -- the box of a Curve is the box of its control points: the curve lies inside it
  local d2 = bs.svg.new(C, {width = 100})
  T.ok(d2:tostring():find('width="100.00"', 1, true))
end)

T.test("write, ending, closing", function()
  local doc = bs.svg.new({{0, 0}, {1, 1}})
  doc:points({{0.5, 0.5}})
  local path = os.tmpname() .. ".svg"
  T.eq(doc:write(path), doc)
  local f = assert(io.open(path))
  local s = f:read("a"); f:close()
  T.eq(s, doc:tostring(), "write and tostring give the same text")
  os.remove(path)
  T.raises("attempt to draw on an ended svg document", function() doc:points({{0, 0}}) end)
  T.fails("EIO", doc.write, doc, "/nonexistent/dir/x.svg")
  T.ok(tostring(doc):match("^bsfit%.Svg %(ended%): "))
  local d2 = bs.svg.new({0, 0, 1, 1})
  d2:close(); d2:close()
  T.raises("attempt to use a closed svg document", function() d2:tostring() end)
  do
    local d3 <close> = bs.svg.new({0, 0, 1, 1})
    d3:marker(0.5, 0.5)
  end
  collectgarbage(); collectgarbage()
end)

T.test("misuse raises with the argument named", function()
  local doc = bs.svg.new({0, 0, 1, 1})
  local C = bs.bezier.new{control_points = {{0, 0}, {1, 1}}}
  T.raises("bad argument #1 to 'new' (box {xmin, ymin, xmax, ymax} expected)", function() bs.svg.new({0, 0, 1}) end)
  T.raises({match = "^bad argument #1 to 'new' %(empty bounding box"}, function() bs.svg.new({1, 0, 0, 1}) end)
  T.raises({match = "^bad argument #1 to 'new' %(empty bounding box"}, function() bs.svg.new(bs.points.new(0, 2)) end)
  T.raises("bad argument #2 to 'new' (field 'width' must be in (0, 1e6])", function() bs.svg.new({0, 0, 1, 1}, {width = 0}) end)
  T.raises("bad argument #2 to 'new' (unknown option 'height')", function() bs.svg.new({0, 0, 1, 1}, {height = 3}) end)
  T.raises("bad argument #1 to 'points' (point 2 has a non-finite coordinate)", function() doc:points({{0, 0}, {0 / 0, 1}}) end)
  T.raises({match = "^bad argument #2 to 'points' %(bad CSS class name"}, function() doc:points({{0, 0}}, "a b") end)
  T.raises("bad argument #3 to 'points' (radius must be positive)", function() doc:points({{0, 0}}, nil, -1) end)
  T.raises({match = "^bad argument #2 to 'polyline' %(bad CSS class name"},
           function() doc:polyline({{0, 0}}, {class = "<x>"}) end)
  T.raises("bad argument #2 to 'curve' (field 'samples' must be in 2..1e8)", function() doc:curve(C, {samples = 1}) end)
  T.raises("bad argument #1 to 'curve' (bsfit.Curve expected, got table)", function() doc:curve({}) end)
  T.raises("bad argument #1 to 'points' (SVG needs 2D or 3D points, got dim 1)", function() doc:points(bs.points.new(2, 1)) end)
  T.raises("bad argument #2 to 'marker' (coordinate is not finite)", function() doc:marker(0, math.huge) end)
end)
