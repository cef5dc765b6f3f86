-- test_ends.lua: auto's open-or-closed decision (docs/auto.md, "Open or closed") on open
-- runs that earlier versions closed without a doubt: arcs of 280 to 340 degrees sampled
-- unevenly (the pieces, an arc that covers the samples, closed them however long the gap
-- against the spacing) and spirals (their gap a few steps, their closing chord across
-- their own turns: closed, the curve crossing itself).
local T = require "tap"
local bs = require "bsfit"
local synth = require "synth"
local auto = require "bsfit.strategy.auto"

local function dist(a, b) return math.sqrt((a[1] - b[1]) ^ 2 + (a[2] - b[2]) ^ 2) end

T.test("open arcs, their gap over 1.5 of their longest step: never closed without a doubt", function()
  local uniform, gauss = synth.rng(8821)
  local tried, open, doubted = 0, 0, 0
  for k = 1, 120 do
    local m, sweep = 20 + (k % 6) * 20, math.rad(280 + 60 * uniform())
    local r, sigma = 10 ^ (2 * uniform()), ({ 0, 1e-4, 1e-3 })[k % 3 + 1]
    local fs = {}
    for j = 1, m do fs[j] = k % 2 == 0 and uniform() or (j - 1) / (m - 1) end
    table.sort(fs)
    local pts = {}
    for j = 1, m do
      local t = fs[j] * sweep
      local s = 2 * sigma * r
      pts[j] = { r * math.cos(t) + s * gauss(), r * math.sin(t) + s * gauss() }
    end
    local longest = 0
    for j = 2, m do longest = math.max(longest, dist(pts[j], pts[j - 1])) end
    if dist(pts[m], pts[1]) > 1.5 * longest then
      tried = tried + 1
      local _, rep = auto.run(bs.points.new(pts))
      T.ok(not rep.closed or rep.closed_ambiguous,
           ("arc of %.0f degrees, %d samples, noise %g: closed without a doubt")
             :format(math.deg(sweep), m, sigma))
      if not rep.closed then open = open + 1
      elseif rep.closed_ambiguous then doubted = doubted + 1 end
    end
  end
  print(("# %d arcs: %d open, %d closed with the doubt said"):format(tried, open, doubted))
  T.ok(tried >= 60, tried .. " arcs tried")
end)

T.test("spirals are open: their closing chord crosses their own turns", function()
  local uniform, gauss = synth.rng(1311)
  local why = 0
  for k = 1, 60 do
    local turns, m = 1.2 + 1.3 * uniform(), 15 + (k % 4) * 15
    local sigma = ({ 0, 1e-3 })[k % 2 + 1]
    local pts = {}
    for j = 1, m do
      local f = k % 3 == 0 and ((j - 1) + 0.8 * (uniform() - 0.5)) / (m - 1) or (j - 1) / (m - 1)
      f = math.min(math.max(f, 0), 1)
      local t, rad = 2 * math.pi * turns * f, 1 + 4 * f
      pts[j] = { rad * math.cos(t) + 5 * sigma * gauss(), rad * math.sin(t) + 5 * sigma * gauss() }
    end
    local C, rep = auto.run(bs.points.new(pts))
    local what = ("spiral of %.2f turns, %d samples, noise %g"):format(turns, m, sigma)
    T.eq(rep.closed, false, what)
    T.ok(not C:is_periodic() and rep.crossings == 0, what .. ": an open curve, no crossing")
    -- where the gap alone would close it, the doubt says why it is open
    for _, w in ipairs(rep.warnings) do
      if w:find("closing it would cross the samples' own path", 1, true) then why = why + 1 end
    end
  end
  print("# " .. why .. " spirals opened by their closing chord (the rest by their gap)")
  T.ok(why >= 10, why .. " of them opened because closing would cross their own path")
  -- and closed = true is still taken as given
  local pts = {}
  for j = 1, 30 do local t = 2 * math.pi * 1.8 * (j - 1) / 29; pts[j] = { (1 + t) * math.cos(t), (1 + t) * math.sin(t) } end
  local C, rep = auto.run(bs.points.new(pts), { closed = true })
  T.ok(rep.closed and C:is_periodic(), "closed = true honoured")
end)

-- Three sides of a quadrilateral whose top is a short side cutting off a sharp apex, the
-- top missing: the gap is like a step, so the spacing alone closes the run, and its lines
-- close it as the triangle of the apex (they run on past both end samples by more than
-- 1.5 of their steps) or, where the apex is beyond their reach, with a free bridge: a
-- rounded top. No sample saw either. Before, all 80 were closed without a doubt; the same
-- quadrilaterals with their top sampled are closed, with none.
T.test("a run its pieces close only over a stretch no sample saw is closed with a doubt", function()
  local uniform = synth.rng(5151)
  local doubted, tried = 0, 0
  for k = 1, 80 do
    local w, h = 10, 10 * (1.5 + 2 * uniform())
    local cut = 0.3 + 0.15 * uniform() -- the top: this fraction of the way down from the apex
    local apex = { w * (0.3 + 0.4 * uniform()), h }
    local function down(p) return { apex[1] + cut * (p[1] - apex[1]), apex[2] + cut * (p[2] - apex[2]) } end
    local v = { { 0, 0 }, { w, 0 }, down { w, 0 }, down { 0, 0 } } -- counter-clockwise
    local per = 4 + k % 5
    local function side(a, b, n, pts) -- n samples from a (included) towards b
      for j = 0, n - 1 do
        local f = j / n
        pts[#pts + 1] = { a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2]) }
      end
    end
    -- open: the left side from the cut down, the base, the right side up to the cut
    local open, closed = {}, {}
    side(v[4], v[1], per, open); side(v[1], v[2], per, open); side(v[2], v[3], per, open)
    open[#open + 1] = v[3]
    for _, p in ipairs(open) do closed[#closed + 1] = p end
    side(v[3], v[4], 2, closed) -- the top sampled: v[3] already there, one sample mid-top
    table.remove(closed, #open) -- (v[3] once)
    local _, rep = auto.run(bs.points.new(open))
    tried = tried + 1
    T.ok(not rep.closed or rep.closed_ambiguous, ("quadrilateral %d, %d per side, top %.3g of the way: "
      .. "three sides closed without a doubt"):format(k, per, cut))
    if rep.closed and rep.closed_ambiguous then doubted = doubted + 1 end
    local _, whole = auto.run(bs.points.new(closed))
    T.ok(whole.closed and not whole.closed_ambiguous, ("quadrilateral %d, %d per side: its four sides "
      .. "closed %s, ambiguous %s"):format(k, per, tostring(whole.closed), tostring(whole.closed_ambiguous)))
  end
  print(("# %d runs of three sides: %d closed with the doubt said"):format(tried, doubted))
end)

-- An outline whose closing chord crosses its own polygon, where the lines either side of the
-- gap meet at a corner no sample saw: the way those lines close it (round the corner) is
-- what must not cross, not the chord. An E or an L with 6 samples on its foot and its back,
-- the 3 of each next to the corner between them left out, and 1 or 3 samples on each other
-- side: its chord, from the middle of the back to the middle of the foot, crossed the
-- lower arm's inner edge, and 9 of these 12 were opened (an E of 3 uneven samples per side
-- at noise 1e-4, opened so, was 170 times the floor off its outline). With 2 samples on
-- the other sides no closing pieces are found, and the E is opened, with the doubt said.
T.test("a section whose closing pieces go round a corner is closed though its chord crosses it", function()
  local shapes = require "shapes_sharp"
  local opened = {}
  for _, name in ipairs { "E", "L" } do
    local o = shapes.letter(name)
    for _, other in ipairs { 1, 3 } do
      for _, rel in ipairs { 0, 1e-4, 1e-3 } do
        local k = 0
        local pts = shapes.sample(o, function()
          k = k + 1
          return (k == 1 or k == #o.prims) and 6 or other
        end, { sigma = rel * shapes.size(o), seed = 7 })
        local kept = {}
        for i = 4, #pts - 3 do kept[#kept + 1] = pts[i] end
        local _, rep = auto.run(bs.points.new(kept))
        if not rep.closed then opened[#opened + 1] = ("%s, %d per other side, noise %g"):format(name, other, rel) end
      end
    end
  end
  T.ok(#opened == 0, "opened: " .. table.concat(opened, "; "))
end)

-- Open arcs whose gap is 1.2 to 1.5 times their longest other step: the gap is then the
-- longest step of the polygon, which a closed section sampled so unevenly shows as well.
-- They were closed without a doubt (a gap up to 1.5 times the longest step was clear);
-- on 600 open parts of the sweep's outlines, 77 were closed without one, 53 now, and the
-- doubt said on 26 of their 600 closed sections where it was on 20.
T.test("open arcs, their gap 1.2 to 1.5 of their longest step: never closed without a doubt", function()
  local uniform, gauss = synth.rng(4417)
  local tried, silent = 0, {}
  for k = 1, 400 do
    local m = 12 + (k % 8) * 6
    local ratio = 1.22 + 0.26 * uniform()
    local sweep = 2 * math.pi / (1 + ratio / (m - 1))
    local r, sigma = 10 ^ (2 * uniform()), ({ 0, 1e-4, 1e-3 })[k % 3 + 1]
    local pts = {}
    for j = 1, m do
      local t = sweep * (j - 1) / (m - 1) * (1 + 0.05 * (uniform() - 0.5) * (k % 2))
      pts[j] = { r * math.cos(t) + 2 * sigma * r * gauss(), r * math.sin(t) + 2 * sigma * r * gauss() }
    end
    local longest = 0
    for j = 2, m do longest = math.max(longest, dist(pts[j], pts[j - 1])) end
    local g = dist(pts[m], pts[1]) / longest
    if g > 1.2 and g <= 1.5 then
      tried = tried + 1
      local _, rep = auto.run(bs.points.new(pts))
      if rep.closed and not rep.closed_ambiguous then
        silent[#silent + 1] = ("%d samples, gap %.2f steps, noise %g"):format(m, g, sigma)
      end
    end
  end
  print(("# %d arcs, %d closed without a doubt"):format(tried, #silent))
  T.ok(tried >= 100, tried .. " arcs tried")
  T.ok(#silent == 0, "closed without a doubt: " .. table.concat(silent, "; "))
end)
