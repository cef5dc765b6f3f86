-- test_sharp_outliers.lua: the auto strategy on sections of lines and arcs carrying gross
-- outliers of tiny weight (issue 14: "points with tiny weights never create a loop"). The
-- outliers are inserted among the samples of tests/lua/shapes_sharp.lua's outlines (about
-- one in ten, up to 15% of the size off), so the trusted samples are the section itself:
-- its pieces are found on them, and the one curve is the one of the section without its
-- outliers. Loops are looked for by an independent check (the polyline of dense samples of
-- the curve, ever closer to every knot), not by bs.geom.self_intersections.
local T = require "tap"
local bs = require "bsfit"
local shapes = require "shapes_sharp"
local synth = require "synth"
local auto = require "bsfit.strategy.auto"

-- the samples of sweep case c with gross outliers of weight w among them: points, weights
local function with_outliers(c, w)
  local uniform = shapes.rng(7 * c.seed + (w == 1e-2 and 1 or 2))
  local pts, wts = {}, {}
  for _, p in ipairs(c.pts) do
    pts[#pts + 1], wts[#wts + 1] = { p[1], p[2] }, 1
    if uniform() < 0.1 then
      pts[#pts + 1] = { p[1] + (uniform() - 0.5) * 0.3 * c.size, p[2] + (uniform() - 0.5) * 0.3 * c.size }
      wts[#wts + 1] = w
    end
  end
  return pts, wts
end

-- whether the section took its pieces because the smooth curve missed a sample (the misfit
-- swap): the smooth curve decides it, and down-weighted outliers still pull that curve
-- (docs/auto.md, Limits)
local swapped = synth.misfit_swap

-- the largest distance between k samples of two curves at the same parameters
local function apart(C1, C2, k)
  local S1, S2, worst = C1:sample(k), C2:sample(k), 0
  for i = 1, k do
    local x1, y1 = S1:get(i)
    local x2, y2 = S2:get(i)
    worst = math.max(worst, math.sqrt((x1 - x2) ^ 2 + (y1 - y2) ^ 2))
  end
  return worst
end

T.test("gross outliers of weight 1e-2 and 1e-3 on every outline: no error, no loop, the pieces of the trusted samples", function()
  local n, pieces, loops = 0, 0, {}
  for c in shapes.sweep_cases { pers = { 4, 10 }, rels = { 0, 1e-3, 3e-3 }, thin = true } do
    local C0, rep0 = auto.run(bs.points.new(c.pts))
    for _, w in ipairs { 1e-2, 1e-3 } do
      local pts, wts = with_outliers(c, w)
      local what = ("%s %d per side noise %g %s, outliers of weight %g"):format(c.name, c.per,
        c.rel, c.uneven and "uneven" or "even", w)
      local ok, C, rep = pcall(auto.run, bs.points.new(pts), { point_weights = bs.vector.new(wts) })
      T.ok(ok, what .. ": " .. tostring(ok or C))
      if ok then
        n = n + 1
        T.eq(rep.closed, rep0.closed, what .. ": closed as without the outliers")
        T.ok(rep.max == rep.max and rep.max < math.huge, what .. ": finite report")
        if synth.polyline_crosses(synth.dense_samples(C)) or rep.crossings > 0 then
          loops[#loops + 1] = what
        end
        if rep0.pieces and not swapped(rep0) then -- the same pieces, the same curve
          pieces = pieces + 1
          T.eq(rep.pieces and #rep.pieces, #rep0.pieces, what .. ": pieces")
          if rep.pieces then
            local d = apart(C, C0, 500)
            T.ok(d <= 1e-12 * c.size, ("%s: %.3g of the size from the curve without outliers")
              :format(what, d / c.size))
          end
        end
      end
    end
  end
  print(("# %d sections with outliers, %d through the pieces; loops: %d"):format(n, pieces, #loops))
  T.eq(#loops, 0, table.concat(loops, "; "))
  T.ok(pieces >= (shapes.thinned and 60 or 200), "the pieces path looked at: " .. pieces)
end)

-- Where the pieces at the noise search's level were refused and the smooth curve then missed
-- a sample by 6 sigma, the section swapped to its pieces (pieces_path, the misfit swap) on
-- every point, but not on the trusted points' path: 8 of the sweep's 390 sections took
-- other pieces (or none) when outliers of weight 1e-2 were among their samples. What differs
-- now is the smooth curve itself, which the outliers still pull (docs/auto.md, Limits): a
-- difference is allowed only where one of the two runs took the swap, and 3 such (a T of
-- 10 samples per side at noise 1e-3 missed a trusted sample by 6.8 sigma with them and not
-- without; a hexagon of 5 the other way round; since fillets are tried at corners,
-- segment_corner_fillets.c, an L with serifs of 4 uneven samples per side at noise 3e-3, whose
-- pieces the swap took without the outliers).
T.test("the sweep with and without down-weighted outliers: the same pieces but where the outliers move the smooth curve", function()
  local n, differ, unexplained = 0, {}, {}
  for c in shapes.sweep_cases { thin = true } do
    local _, rep0 = auto.run(bs.points.new(c.pts))
    local pts, wts = with_outliers(c, 1e-2)
    local _, rep = auto.run(bs.points.new(pts), { point_weights = bs.vector.new(wts) })
    n = n + 1
    if (rep0.pieces and #rep0.pieces) ~= (rep.pieces and #rep.pieces) then
      local what = ("%s %d per side noise %g%s: %s pieces without, %s with"):format(c.name,
        c.per, c.rel, c.uneven and " uneven" or "", rep0.pieces and #rep0.pieces or "no",
        rep.pieces and #rep.pieces or "no")
      local list = (swapped(rep0) or swapped(rep)) and differ or unexplained
      list[#list + 1] = what
    end
  end
  print(("# %d sections, %d with other pieces with the outliers where one run took the swap, %d else")
    :format(n, #differ, #unexplained))
  T.eq(#unexplained, 0, table.concat(unexplained, "; "))
  T.ok(#differ <= 3, table.concat(differ, "; "))
end)

T.test("smooth shapes with gross outliers of weight 1e-2: the count search judges fits by the trusted points", function()
  -- an outlier of weight 1e-2 a tenth of the size off weighs as much as a sample 30 sigma
  -- off: judged by every point, the search added control points to reach the outliers
  -- (1.44 times the count without them over this sweep; 1.13 judged by the trusted points)
  local smooth, names = synth.smooth_shapes()
  local with, without = 0, 0
  for _, name in ipairs(names) do
    for _, m in ipairs { 40, 100, 300 } do
      for _, sigma in ipairs { 1e-3, 3e-3 } do
        for seed = 1, 3 do
          local P = synth.noisy(synth.sample_smooth(smooth[name], m, seed == 2), sigma, seed)
          local uniform = synth.rng(31 * seed + m)
          local pts, w = {}, {}
          for i = 1, #P do
            local x, y = P:get(i)
            pts[#pts + 1], w[#w + 1] = { x, y }, 1
            if uniform() < 0.1 then
              pts[#pts + 1], w[#w + 1] = { x + (uniform() - 0.5) * 0.6, y + (uniform() - 0.5) * 0.6 }, 1e-2
            end
          end
          local _, rep0 = auto.run(P)
          local _, rep = auto.run(bs.points.new(pts), { point_weights = bs.vector.new(w) })
          without, with = without + rep0.count, with + rep.count
        end
      end
    end
  end
  print(("# control points: %d with the outliers, %d without"):format(with, without))
  T.ok(with <= 1.2 * without, ("%d control points with the outliers, %d without"):format(with, without))
end)
