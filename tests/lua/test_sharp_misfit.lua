-- test_sharp_misfit.lua: a noisy section of lines and arcs whose two noise estimates
-- disagree (the lines' and arcs' own residual against the windows', by 25% or more, or no
-- level of theirs matching) keeps the smooth path; where that smooth curve then misses its
-- own samples by more than 6 sigma, auto fits the lines and arcs at the noise they show
-- (every other test of bsfit.strategy.noisy_pieces passed) instead. Sections that no other
-- sweep uses (own seeds), 8 and 10 uneven samples per side at noise 1e-4 and 3e-4 of the
-- size: the swap happened on none before (a D of 10 uneven samples per side had bulged 1.15
-- from its true outline, 55 times the floor), and wherever it happens now the curve is
-- nearer the true outline than the smooth curve it replaced.
-- Likewise pieces that a test of the screen refused at a noise level that agrees with the
-- windows' (a bridge, a weak corner between sides too short to soften), where the smooth
-- curve misses a sample by more than 6 times that level (third test).
local T = require "tap"
local bs = require "bsfit"
local shapes = require "shapes_sharp"
local synth = require "synth"
local auto = require "bsfit.strategy.auto"

local swapped = synth.misfit_swap

T.test("a smooth curve missing its samples by 6 sigma gives way to the lines and arcs", function()
  local n, swaps, within, smooth_within = 0, 0, 0, 0
  for c in shapes.sweep_cases { pers = { 8, 10 }, rels = { 1e-4, 3e-4 }, unevens = { true },
      draws = 4,
      seed = function(k, per, j, d) return 77000 + 1000 * k + 10 * per + j + 100000 * d end } do
    local P = bs.points.new(c.pts)
    local C, rep = auto.run(P)
    n = n + 1
    if swapped(rep) then
      swaps = swaps + 1
      local what = ("%s %d per side noise %g draw %d"):format(c.name, c.per, c.rel, c.draw)
      T.ok(rep.pieces ~= nil and rep.pieces_rejected == nil, what .. ": the pieces, reported")
      -- the smooth curve it replaced: the same run with the assemble step switched off
      local S, srep = auto.run(P, { assemble = false })
      T.ok(srep.max > 6 * math.min(srep.sigma, rep.pieces_sigma) and rep.max < srep.max,
           what .. (": %.3g from a sample, the smooth curve %.3g"):format(rep.max, srep.max))
      local r, rs = shapes.floor_ratio(bs, C, c), shapes.floor_ratio(bs, S, c)
      T.ok(r < rs, what .. (": %.3g of the floor, the smooth curve %.3g"):format(r, rs))
      if r <= 1 then within = within + 1 end
      if rs <= 1 then smooth_within = smooth_within + 1 end
    end
  end
  print(("# %d sections: %d swapped, %d of them within 3 sigma + 1e-3 of the size (%d smooth)")
    :format(n, swaps, within, smooth_within))
  T.ok(swaps >= 5, swaps .. " swaps")
  T.ok(within >= swaps // 2, within .. " of the swapped within the floor")
end)

-- A count, a tolerance or a replaced step asks for the smooth curve: it is kept, however far
-- it misses (the swap ignored a count of 8 asked for, and the curve's report then mixed the
-- two paths).
T.test("a count, a tolerance or a replaced step keeps the smooth curve", function()
  local n = 0
  local D = { names = { "D" }, pers = { 10 }, rels = { 1e-4 }, unevens = { true } }
  for c in shapes.sweep_cases(D) do
    local P = bs.points.new(c.pts)
    local _, rep = auto.run(P)
    T.ok(swapped(rep), "the D swaps without options")
    for _, o in ipairs { { count = 8 }, { tol = 0.5 }, { corners = {} }, { segment = {} } } do
      local C2, r2 = auto.run(P, o)
      local what = next(o)
      T.ok(not swapped(r2) and r2.pieces == nil, what .. ": the smooth curve")
      if o.count then T.eq(C2:distinct(), 8, "count honoured") end
      n = n + 1
    end
  end
  T.eq(n, 4)
end)

-- Sparse sections (3 to 6 samples per side) whose pieces a test of the screen refused at a
-- noise level s that agrees with the windows' (a bridge; a weak corner between sides of 3
-- samples, which cannot be softened, where other corners are strong): the windows read the bends
-- between so few samples as noise, and the smooth curve misses a sample by 10 to 50 s. Where
-- it misses one by more than 6 s, the pieces at s are tried leniently (bridges and such
-- corners kept) through every other test (within 6 s of every sample, no crossing, nearer
-- the samples than the smooth curve). None swapped before; a T of 3 uneven samples per side
-- at noise 1e-3 went from 17 to 1.2 times the floor, an L with serifs at 1e-4 from 47 to 0.4.
-- A few swaps land no nearer the truth (both curves far off): at most one in ten.
local function disagreement(w)
  return w:find("(noise of the pieces", 1, true) or w:find("(no noise level", 1, true)
end

T.test("pieces a screen test refused give way where the smooth curve misses by 6 times their noise", function()
  local n, swaps, nearer, within, smooth_within = 0, 0, 0, 0, 0
  for c in shapes.sweep_cases { pers = { 3, 4, 5, 6 }, rels = { 1e-4, 1e-3 }, draws = 3,
      seed = function(k, per, j, d) return 5000 + 1000 * k + 10 * per + j + 100000 * d end } do
    local P = bs.points.new(c.pts)
    local C, rep = auto.run(P)
    n = n + 1
    local w = swapped(rep)
    if w and not disagreement(w) then
      swaps = swaps + 1
      local what = ("%s %d per side noise %g%s"):format(c.name, c.per, c.rel, c.uneven and " uneven" or "")
      T.ok(rep.pieces ~= nil and rep.pieces_rejected == nil and rep.pieces_sigma > 0,
           what .. ": the pieces, reported")
      local S, srep = auto.run(P, { assemble = false })
      T.ok(srep.max > 6 * rep.pieces_sigma and rep.max < srep.max and rep.max <= 6 * rep.pieces_sigma,
           what .. (": %.3g from a sample, the smooth curve %.3g, noise %.3g"):format(rep.max,
           srep.max, rep.pieces_sigma))
      T.eq(rep.crossings, 0, what .. ": crossings")
      local r, rs = shapes.floor_ratio(bs, C, c), shapes.floor_ratio(bs, S, c)
      print(("# %s: %.3g -> %.3g (%s)"):format(what, rs, r, w:match("%((.*)%)$")))
      if r < rs then nearer = nearer + 1 end
      if r <= 1 then within = within + 1 end
      if rs <= 1 then smooth_within = smooth_within + 1 end
    end
  end
  print(("# %d sections: %d swapped on a screen test, %d nearer the truth, %d within the floor (%d smooth)")
    :format(n, swaps, nearer, within, smooth_within))
  -- (16 swaps before pieces refused at the noise level and the two above were tried one
  -- level below it, noisy_pieces.find: 9 of those sections now take their pieces there)
  T.ok(swaps >= 5, swaps .. " swaps")
  T.ok(nearer >= 0.9 * swaps, nearer .. " of the swapped nearer the true outline")
  T.ok(within > smooth_within, within .. " of the swapped within the floor")
end)
