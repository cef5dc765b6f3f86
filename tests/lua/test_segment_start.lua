-- test_segment_start.lua: a closed section's segmentation does not depend on which of its
-- samples the data happen to start at (a scan's cut has no preferred start). The maximal
-- runs resume each start from the run before it (segment_runs.c), and the scan began at the
-- data's first sample: of 390 sections of the sweep's outlines on seeds of their own, each
-- started at two other random samples, 23 read another noise, 10 another cover at their
-- true noise and 10 came out of `auto` with other pieces. The scan now begins after the
-- longest step between samples. Exact sections too (the same runs), and dense ones, read
-- on every k-th sample: from that same sample now, from the data's first before (of 26
-- sections of 20 and 100 samples per side, 3 and 26 read another noise from another
-- start). A sweep (BSFIT_SWEEPS): 1092 shifted sections, 10 s.
local T = require "tap"
local bs = require "bsfit"
local shapes = require "shapes_sharp"
local auto = require "bsfit.strategy.auto"

-- pieces as a list of "kind count first" with first the sample's index in the unshifted
-- data (so the same pieces from any start read the same), sorted
local function signature(pieces, shift, m)
  local t = {}
  for _, p in ipairs(pieces or {}) do
    t[#t + 1] = ("%s%d@%d"):format(p.kind, p.count, (p.first - 1 + shift) % m + 1)
  end
  table.sort(t)
  return table.concat(t, " ")
end

-- the section started at sample shift + 1: its noise estimate, its cover at noise sigma and
-- auto's pieces (told it is closed: left to decide, auto reads the gap between the last and
-- first samples, which is where the data start; an E of 3 uneven samples per side was then
-- open from one start and closed from the next)
local function read(pts, shift, sigma)
  local m, q = #pts, {}
  for i = 1, m do q[i] = pts[(i - 1 + shift) % m + 1] end
  local P = bs.points.new(q)
  local s = bs.geom.segment_sigma(P, { closed = true })
  local cover = signature(bs.geom.segment(P, { closed = true, sigma = sigma }), shift, m)
  local _, rep = auto.run(P, { closed = true })
  return s, cover, (rep.pieces and "pieces: " or "smooth: ") .. signature(rep.pieces, shift, m)
end

T.test("a closed section reads the same from any start: noise, cover, auto's pieces", function()
  local uniform = shapes.rng(4321)
  local n = 0
  for c in shapes.sweep_cases { rels = { 0, 1e-4, 1e-3, 3e-3 },
                                seed = function(k, per, j) return 77000 + 1000 * k + 10 * per + j end } do
    local m = #c.pts
    local s0, cover0, auto0 = read(c.pts, 0, c.sigma)
    for _ = 1, 2 do
      local shift = 1 + math.floor(uniform() * (m - 1))
      local s, cover, got = read(c.pts, shift, c.sigma)
      local what = ("%s, %d per side, noise %g%s, from sample %d"):format(c.name, c.per, c.rel,
        c.uneven and ", uneven" or "", shift + 1)
      T.ok(s == s0, ("%s: noise %.17g, %.17g from sample 1"):format(what, s, s0))
      T.eq(cover, cover0, what .. ": cover at the true noise")
      T.eq(got, auto0, what .. ": auto's pieces")
      n = n + 1
    end
  end
  T.ok(n >= 1000, ("%d shifted sections"):format(n))
end)

T.test("a dense closed section reads the same from any start (its every k-th sample)", function()
  local uniform = shapes.rng(8765)
  local n = 0
  for c in shapes.sweep_cases { pers = { 100 }, rels = { 1e-4, 1e-3 }, unevens = { false },
                                seed = function(k, per, j) return 78000 + 1000 * k + 10 * per + j end } do
    local m = #c.pts
    local s0, cover0, auto0 = read(c.pts, 0, c.sigma)
    local shift = 1 + math.floor(uniform() * (m - 1))
    local s, cover, got = read(c.pts, shift, c.sigma)
    local what = ("%s, %d samples, noise %g, from sample %d"):format(c.name, m, c.rel, shift + 1)
    T.ok(s == s0, ("%s: noise %.17g, %.17g from sample 1"):format(what, s, s0))
    T.eq(cover, cover0, what .. ": cover at the true noise")
    T.eq(got, auto0, what .. ": auto's pieces")
    if m > 500 then n = n + 1 end
  end
  T.ok(n >= 20, ("%d dense sections"):format(n))
end)

-- Above 5000 samples `auto` reads the windows' noise (rep.sigma, which the pieces' noise
-- must agree with) on every k-th sample; from the data's first sample that was another
-- subsample from each start: a rounded rectangle of 10^5 samples at noise 1e-4 read 0.00673
-- to 0.0069 and went through its pieces from two starts of three. Now from where the
-- segmentation reads it (bs.geom.segment_start). Outlines of the sweep at 8000 to 20000
-- samples, noise 1e-4 and 1e-3, each read from two random starts.
T.test("a large closed section reads the same noise and pieces from any start", function()
  local uniform = shapes.rng(8642)
  local n, names = 0, { "rrect", "hexagon", "T", "keyhole", "gear", "D" }
  local all = shapes.all()
  for k, name in ipairs(names) do
    for j, rel in ipairs { 1e-4, 1e-3 } do
      local o = all[name]
      local per = math.floor((8000 + 12000 * uniform()) / #o.prims)
      local sigma = rel * shapes.size(o)
      local pts = shapes.sample(o, per, { sigma = sigma, seed = 91000 + 10 * k + j, uneven = j == 2 })
      local m = #pts
      local reads = {}
      for r = 1, 3 do
        local shift = r == 1 and 0 or math.floor(uniform() * m)
        local q = {}
        for i = 1, m do q[i] = pts[(i - 1 + shift) % m + 1] end
        local _, rep = auto.run(bs.points.new(q), { closed = true })
        reads[r] = { sigma = rep.sigma, shift = shift,
                     pieces = (rep.pieces and "pieces: " or "smooth: ") .. signature(rep.pieces, shift, m) }
      end
      for r = 2, 3 do
        local what = ("%s of %d samples, noise %g, from sample %d"):format(name, m, rel, reads[r].shift + 1)
        T.ok(reads[r].sigma == reads[1].sigma, ("%s: noise %.17g, %.17g from sample 1"):format(what,
          reads[r].sigma, reads[1].sigma))
        T.eq(reads[r].pieces, reads[1].pieces, what .. ": pieces")
        n = n + 1
      end
    end
  end
  T.ok(n == 24, ("%d shifted sections"):format(n))
end)
