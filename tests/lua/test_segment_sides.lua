-- test_segment_sides.lua: short sides between two long ones under noise (issue 14). A step
-- cut into a side of a polygon (a notch 8 to 32 sigma deep) has two short sides whose
-- samples lie within the tolerance (4 sigma) of the long sides' lines next to them: each
-- long line took a few of them, the two met nowhere between them, and the section was
-- bridged (its pieces refused). The segmentation now tries their end samples as the side
-- between them (bsfit__split_bridges, src/core/segment_corner_arcs.c). The polygons are
-- random (4 to 7 vertices round a circle, the notch in the longest side), sampled 3 to 6
-- times per side, evenly and unevenly, at noise 5e-4 to 3e-3 of their size.
local T = require "tap"
local bs = require "bsfit"
local shapes = require "shapes_sharp"
local auto = require "bsfit.strategy.auto"

-- A random polygon with a rectangular notch in its longest side: outline (shapes_sharp's
-- form), its noise and samples per side.
local function notched(uniform)
  local v = shapes.random_vertices(uniform)
  local n, longest, len = #v, 1, 0
  for i = 1, n do
    local l = shapes.dist(v[i], v[i % n + 1])
    if l > len then longest, len = i, l end
  end
  local p, q = v[longest], v[longest % n + 1]
  local ux, uy = (q[1] - p[1]) / len, (q[2] - p[2]) / len
  local nx, ny = uy, -ux -- into the polygon (its vertices run counter-clockwise)
  local sigma = 20 * (5e-4 + 2.5e-3 * uniform())
  local depth, width = sigma * (8 + 24 * uniform()), len * (0.15 + 0.2 * uniform())
  local t0 = (len - width) * (0.2 + 0.6 * uniform())
  local function at(t, d) return { p[1] + t * ux - d * nx, p[2] + t * uy - d * ny } end
  local w = {}
  for i = 1, n do
    w[#w + 1] = v[i]
    if i == longest then
      w[#w + 1] = at(t0, 0)
      w[#w + 1] = at(t0, depth)
      w[#w + 1] = at(t0 + width, depth)
      w[#w + 1] = at(t0 + width, 0)
    end
  end
  return shapes.polygon(w), sigma, 3 + math.floor(4 * uniform())
end

-- the generated sections, each once: {o, sigma, per, pts, size}
local function sections(seed, count) return shapes.random_sections(seed, count, notched) end

-- At the true noise, 400 sections: 130 were read as their own lines, one per side and no
-- free piece, and 256 had a free piece (a bridge); now 252 and 112. The rest: an arc across
-- a notch's corner (the cover buys one arc of 3 parameters before two lines of 4), or a
-- short side's samples too few or too crowded for any line within the tolerance.
T.test("notched polygons at their true noise: the short sides are lines of their own", function()
  local n, right, bridged = 0, 0, 0
  for c in sections(7, 400) do
    local pieces = bs.geom.segment(bs.points.new(c.pts), { closed = true, sigma = c.sigma })
    local lines, free = 0, false
    for _, p in ipairs(pieces) do
      if p.kind == "line" then lines = lines + 1 end
      if p.kind == "free" then free = true end
    end
    n = n + 1
    if free then bridged = bridged + 1 end
    if not free and lines == #c.o.prims then right = right + 1 end
  end
  print(("# %d notched polygons: %d as their own lines, %d with a free piece"):format(n, right, bridged))
  T.ok(right >= 240, right .. " as their own lines")
  T.ok(bridged <= 120, bridged .. " with a free piece")
end)

-- auto end to end (the noise read off the sections): 91 of 300 were within the floor (3
-- sigma + 1e-3 of the size) before, now 149; none crosses itself.
T.test("notched polygons through auto: within the floor", function()
  local n, within = shapes.auto_within(T, bs, auto, sections(11, 300))
  print(("# %d notched polygons: %d within the floor"):format(n, within))
  T.ok(within >= 145, within .. " within the floor")
end)
