-- bench_segment_dense.lua: dense exact sections (docs/auto.md, "Dense exact sections"):
-- bs.geom.segment and the whole auto run on a circle, a D shape and free-form outlines (an
-- ellipse, a five-lobed bump) of 10^4 and 10^5 exact samples, the minimum of a few runs.
-- The free-form ones show what the segmentation costs where every run of 30-50 samples is
-- an osculating arc (linear in the samples); auto screens them on a subsample and keeps
-- the smooth path.
--   bsfit tests/bench/bench_segment_dense.lua
package.path = (arg[0]:match("^(.*)/[^/]*$") or ".") .. "/?.lua;" .. package.path
local bs = require "bsfit"
local auto = require "bsfit.strategy.auto"
local bench = require "benchlib"

-- m samples of the closed curve f(a), a in [0, 2 pi), at the middles of m equal steps
local function closed(m, f)
  local t = {}
  for i = 0, m - 1 do t[#t + 1] = f(2 * math.pi * (i + 0.5) / m) end
  return bs.points.new(t)
end

local function circle(a) return { 1e3 + 5 * math.cos(a), -2e3 + 5 * math.sin(a) } end
local function ellipse(a) return { 7 * math.cos(a), 3 * math.sin(a) } end
local function bump(a)
  local r = 5 + 0.6 * math.sin(5 * a)
  return { r * math.cos(a), r * math.sin(a) }
end

-- the least time of `runs` calls of f, in ms
local function least(f, runs) return bench.least(f, runs) * 1000 end

for _, m in ipairs { 10000, 100000 } do
  for _, c in ipairs {
    { "circle far from the origin", closed(m, circle) }, { "D shape", bench.dshape(m) },
    { "ellipse", closed(m, ellipse) }, { "five-lobed bump", closed(m, bump) },
  } do
    local P = c[2]
    local pieces = bs.geom.segment(P, { closed = true })
    local n = { line = 0, arc = 0, free = 0 }
    for _, p in ipairs(pieces) do n[p.kind] = n[p.kind] + 1 end
    local seg = least(function() bs.geom.segment(P, { closed = true }) end, 5)
    local _, rep = auto.run(P)
    local whole = least(function() auto.run(P) end, 5)
    print(("%-27s %6d samples: segment %8.2f ms (%d lines, %d arcs, %d free); auto %7.2f ms "
           .. "(%s, measure %.2f ms, max %.2g)"):format(c[1], m, seg, n.line, n.arc, n.free, whole,
           rep.pieces and "pieces" or "smooth", rep.times.measure or 0, rep.max))
  end
end
