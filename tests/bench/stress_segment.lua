-- stress_segment.lua: validity of bs.geom.segment's lines on families no floor is tuned on,
-- as a tool to look for bugs (it asserts nothing; the families it found bugs in are tests
-- now: test_segment_corner_fillets 4, test_sharp_noisy 5). Every line must run from its
-- start to its end along its reported tangent (sin <= 1e-9, forwards). Lists each line
-- that does not, then the counts:
--   closed  the sweep's outlines (3 to 30 samples per side, noise 1e-4 to 1e-2), closed,
--           read at the noise bs.geom.segment_sigma finds;
--   open    the same with a quarter to a half of each dropped, read as open;
--   coarse  the sweep's sections read at 1%, 2% and 5% of their size (far above their
--           noise: 14 of 2507 lines off until two lines meeting at one point at both
--           joins were no longer a cover, test_segment_noisy_joins 4).
--   bsfit tests/bench/stress_segment.lua [SEED] [COUNT]   (from the source tree, ~10 s)
local here = arg[0]:match("^(.*)/[^/]*$") or "."
package.path = here .. "/../lua/?.lua;" .. package.path
local bs = require "bsfit"
local shapes = require "shapes_sharp"

local seed, count = tonumber(arg[1] or 5), tonumber(arg[2] or 1000)

-- the lines of pieces, and how many leave their reported tangent, each printed with `what`
local function lines_off(pieces, what)
  local lines, off = shapes.lines_off_tangent(pieces)
  for _, b in ipairs(off) do
    local p = pieces[b.i]
    print(("%s: line %d (samples %d..+%d) off its tangent, sin %.3g"):format(what, b.i, p.first,
      p.count, b.sin))
  end
  return lines, #off
end

local totals = {}
local function add(family, lines, off)
  local t = totals[family] or { lines = 0, off = 0 }
  totals[family] = t
  t.lines, t.off = t.lines + lines, t.off + off
end

local uniform, all, names = shapes.rng(seed), shapes.all(), shapes.names()
for k = 1, count do
  local name = names[1 + math.floor(#names * uniform())]
  local o = all[name]
  local rel = ({ 1e-4, 1e-3, 3e-3, 1e-2 })[1 + math.floor(4 * uniform())]
  local per = ({ 3, 4, 6, 10, 30 })[1 + math.floor(5 * uniform())]
  local pts = shapes.sample(o, per, { seed = k, sigma = rel * shapes.size(o), uneven = uniform() < 0.5 })
  local what = ("%s %d per side noise %g (case %d)"):format(name, per, rel, k)
  local part = shapes.open_part(pts, uniform)
  for _, f in ipairs { { "closed", pts, true }, { "open", part, false } } do
    add(f[1], lines_off(shapes.segment_at_own_noise(bs, bs.points.new(f[2]), f[3]), what .. " " .. f[1]))
  end
end
for c in shapes.sweep_cases { pers = { 3, 4, 6, 10 }, rels = { 1e-3, 3e-3 } } do
  local P = bs.points.new(c.pts)
  for _, f in ipairs { 0.01, 0.02, 0.05 } do
    local what = ("%s %d per side noise %g%s at %g of the size"):format(c.name, c.per, c.rel,
      c.uneven and " uneven" or "", f)
    add("coarse", lines_off(bs.geom.segment(P, { closed = true, sigma = f * c.size }), what))
  end
end
for _, family in ipairs { "closed", "open", "coarse" } do
  local t = totals[family] or { lines = 0, off = 0 }
  print(("%-7s %6d lines, %d off their reported tangent"):format(family, t.lines, t.off))
end
