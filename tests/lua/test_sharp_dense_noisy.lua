-- test_sharp_dense_noisy.lua: the auto strategy on dense noisy sections of lines and arcs
-- (issue 14; what a scan's cloud sections are): the 13 outlines of shapes_sharp at 100 and
-- 300 samples per side (400 to 12000 samples), noise 1e-4 to 3e-3 of the size, even and
-- uneven, against their true outlines; and dense noisy smooth shapes, which must stay one
-- smooth curve.
--
-- Before, sections of more than 500 noisy samples always took the smooth path (the noise
-- search over levels cost m times the run length, and the cover cut a long side wherever
-- one sample lay past 4 sigma): 14 of these 156 sections went through their pieces and
-- 106 were within the issue's floor. The noise is now read off 500 evenly spread samples,
-- the cover of a section of more than 500 is found on every k-th sample and moved onto
-- all of them (segment_dense.c), and a corner's evidence counts the samples within
-- 32 sigma of it (and twice the gap between its samples, and at most a tenth of the size):
-- 107 went through their pieces, 142 were within the floor (124 before the gap's reach);
-- since a line run sampled more densely than the noise counts the tolerances it spans
-- (the serifs' sides were free runs), 128 and 148; 127 and 147 since a piece keeps the
-- distinct samples its model needs when its boundary moves; 128 and 150 since an arc's run
-- from samples whose first circle went astray is tried up to where the next run ends; 132
-- and 152 since a softened bend's free run no longer loops; 136 and 152 since the loop
-- check samples ever closer to the corners (hooks and zig-zags at corners it had missed)
-- and an arc whose circle fit fails on its samples is their line.
local T = require "tap"
local bs = require "bsfit"
local shapes = require "shapes_sharp"
local synth = require "synth"
local auto = require "bsfit.strategy.auto"

-- the shares reached (docs/auto.md, "Dense noisy sections")
-- Radii as test_sharp_noisy's: within 2% where the samples fix them to 1% (radius_se),
-- within 3 radius_se (or 2%) elsewhere, and of all the share within 2% (since fillets are
-- made where their samples fix the radius less well: 139 -> 145 through the pieces, 153
-- within as before; of the third the sanitizer build runs, 51 -> 50 within)
-- (radii 0.83: 111 of 133 within 2% since a dense section is read from the sample after
-- its longest step, bsfit__closed_start; 111 of 130 while it was read from the data's first
-- sample. That share moves with which samples the reading takes: from random starts before,
-- 112 of 130 and 107 of 125; from 1, 2, 3 and 5 samples after the longest step, 97 of 119,
-- 110 of 128, 107 of 126 and 103 of 128: 0.80 to 0.86)
local FLOOR = { pieces = 140, within = 150, corners = 0.98, radii = 0.83, radii_fixed = 0.95,
                radii_uncertain = 0.85 }
-- the sanitizer build's third of the sweep (shapes.thinned): its own counts, measured
if shapes.thinned then
  FLOOR = { pieces = 45, within = 50, corners = 0.98, radii = 0.7, radii_fixed = 0.95,
            radii_uncertain = 0.85 }
end

T.test("dense noisy sections of lines and arcs go through their pieces: corners within a sample, "
       .. "radii within 2%, no loop", function()
  local tot = { n = 0, pieces = 0, within = 0, c = 0, cok = 0, r = 0, rok = 0, rf = 0, rfok = 0, ruok = 0,
                joins = 0, kinks = 0, kink = 0 }
  for c in shapes.sweep_cases { pers = { 100, 300 }, thin = true } do
    local what = ("%s %d per side noise %g %s"):format(c.name, c.per, c.rel, c.uneven and "uneven" or "even")
    local ok, C, rep = pcall(auto.run, bs.points.new(c.pts))
    T.ok(ok, what .. ": " .. tostring(ok or C))
    if ok then
      T.eq((bs.geom.self_intersections(C, 2000)), 0, what .. ": self-intersection")
      T.ok(rep.max < math.huge, what .. ": finite report")
      local ratio = shapes.floor_ratio(bs, C, c)
      local f = shapes.features_found(c.o, c.pts, rep.pieces)
      tot.n = tot.n + 1
      if rep.pieces then tot.pieces = tot.pieces + 1 end
      if ratio <= 1 then tot.within = tot.within + 1 end
      tot.c, tot.cok, tot.r, tot.rok = tot.c + f.corners, tot.cok + f.corners_ok, tot.r + f.radii, tot.rok + f.radii_ok
      tot.rf, tot.rfok, tot.ruok = tot.rf + f.radii_fixed, tot.rfok + f.radii_fixed_ok, tot.ruok + f.radii_uncertain_ok
      local kink, over, joins, opposed = shapes.tangent_kinks(C, rep, 0.1)
      T.eq(opposed, 0, what .. ": a tangent join whose pieces run opposite ways")
      tot.joins, tot.kinks, tot.kink = tot.joins + joins, tot.kinks + over, math.max(tot.kink, kink)
    end
  end
  print(("# %d sections: %d through the pieces, %d within 3 sigma + 1e-3; corners %d/%d within a "
         .. "sample, radii %d/%d within 2%%"):format(tot.n, tot.pieces, tot.within, tot.cok, tot.c, tot.rok, tot.r))
  print(("# radii the samples fix to 1%%: %d of %d within 2%%; the others: %d of %d within 2%% or 3 radius_se")
    :format(tot.rfok, tot.rf, tot.ruok, tot.r - tot.rf))
  T.ok(tot.pieces >= FLOOR.pieces, ("%d sections through the pieces"):format(tot.pieces))
  T.ok(tot.within >= FLOOR.within, ("%d sections within the floor"):format(tot.within))
  T.ok(tot.cok >= FLOOR.corners * tot.c, ("corners within a sample: %d of %d"):format(tot.cok, tot.c))
  T.ok(tot.rok >= FLOOR.radii * tot.r, ("radii within 2%%: %d of %d"):format(tot.rok, tot.r))
  T.ok(tot.rfok >= FLOOR.radii_fixed * tot.rf,
       ("radii the samples fix to 1%%, within 2%%: %d of %d"):format(tot.rfok, tot.rf))
  T.ok(tot.ruok >= FLOOR.radii_uncertain * (tot.r - tot.rf),
       ("other radii within 3 radius_se: %d of %d"):format(tot.ruok, tot.r - tot.rf))
  -- G1 as drawn at every tangent join between lines and arcs: fillets between two lines are
  -- drawn tangent to both (8 of 134 joins turned by up to 0.44 degrees before)
  print(("# tangent joins: %d, %d turn by more than 0.1 degrees as drawn, the most %.3g")
    :format(tot.joins, tot.kinks, tot.kink))
  T.eq(tot.kinks, 0, "tangent joins turning by more than 0.1 degrees")
end)

-- An arc whose first samples follow a sampling gap at its corner: those samples bow less
-- than the noise, the circle fitted to them went astray and the arc's run from them ended
-- a few samples on, so a line across the corner took them (segment_runs.c, extend_arc_runs).
-- Keyholes of 60 and 150 samples per side, even and uneven, noise 1e-3 and 3e-3, six
-- draws the other sweeps do not use: 39 of 48 were within the floor, 47 now.
T.test("an arc's first samples after a gap at its corner stay on the arc (48 keyholes)", function()
  local n, within = 0, 0
  local function seed(k, per, j, d) return 77777 + 1000 * k + 10 * per + j + 100000 * d end
  local cases = shapes.sweep_cases { names = { "keyhole" }, pers = { 60, 150 }, draws = 6,
                                     seed = seed }
  for c in cases do
    if c.rel > 1e-4 then
      local what = ("keyhole %d per side noise %g draw %d"):format(c.per, c.rel, c.draw)
      local C = auto.run(bs.points.new(c.pts))
      T.eq((bs.geom.self_intersections(C, 2000)), 0, what .. ": self-intersection")
      n = n + 1
      if shapes.floor_ratio(bs, C, c) <= 1 then within = within + 1 end
    end
  end
  print(("# %d keyholes: %d within 3 sigma + 1e-3"):format(n, within))
  T.ok(within >= 45, ("%d of %d keyholes within the floor"):format(within, n))
end)

-- Fillets read as lines meeting at weak corners, each corner softened into a bend of two
-- samples (sharp.soften): the free run's cubic had end tangents as long as the polyline
-- through its samples, which noise makes several times its chord where the samples are
-- closer than the noise, and a count that interpolated a sample 2.5 sigma off; its ends
-- overshot into a small loop, the pieces' curve crossed itself and the section lost its
-- corners to the smooth path (sharp.lua, free_length and explains_as_noise). Filleted
-- hexagons and pentagons and rounded rectangles of 100 samples per side, noise 1e-3 and
-- 3e-3, even and uneven, five draws the other sweeps do not use: 38 of 60 went through
-- their pieces, 58 were within the floor, 33 had every corner; now 47, 60 and 42.
T.test("dense noisy filleted outlines: a softened bend's free run does not loop", function()
  local n, pieces, within, every_corner = 0, 0, 0, 0
  local function seed(k, per, j, d) return 55555 + 1000 * k + 10 * per + j + 100000 * d end
  local cases = shapes.sweep_cases { names = { "hexagon", "pentagon", "rrect" }, pers = { 100 },
                                     rels = { 1e-3, 3e-3 }, draws = 5, seed = seed }
  for c in cases do
    local what = ("%s noise %g draw %d"):format(c.name, c.rel, c.draw)
    local C, rep = auto.run(bs.points.new(c.pts))
    T.eq((bs.geom.self_intersections(C, 2000)), 0, what .. ": self-intersection")
    local f = shapes.features_found(c.o, c.pts, rep.pieces)
    n = n + 1
    if rep.pieces then pieces = pieces + 1 end
    if shapes.floor_ratio(bs, C, c) <= 1 then within = within + 1 end
    if f.corners > 0 and f.corners_ok == f.corners then every_corner = every_corner + 1 end
  end
  print(("# %d filleted outlines: %d through the pieces, %d within 3 sigma + 1e-3, %d with every "
         .. "corner"):format(n, pieces, within, every_corner))
  T.ok(pieces >= 45, ("%d of %d through the pieces"):format(pieces, n))
  T.ok(within >= 60, ("%d of %d within the floor"):format(within, n))
  T.ok(every_corner >= 40, ("%d of %d with every corner"):format(every_corner, n))
end)

-- The bend itself: two lines meeting at 15, 30 and 45 degrees, sampled every 1/4, 1/2 and
-- 1 sigma at noise sigma, 20 draws each, segmented at sigma; where the corner is found,
-- sharp.soften makes it a bend and sharp.assemble the curve. The feet of the samples next
-- to the corner were out of order (one past the corner) and the free run's tangents as long
-- as its noisy polyline: 60 of the 168 bends crossed themselves; 10 now (the rest: the
-- free run's own samples out of order; auto refuses such pieces, the smooth path remains).
T.test("a corner softened between dense noisy lines: the bend seldom loops", function()
  local sharp = require "bsfit.strategy.sharp"
  local bends, loops = 0, 0
  for _, turn in ipairs { 15, 30, 45 } do
    for _, h in ipairs { 0.25, 0.5, 1 } do
      for draw = 1, 20 do
        local _, gauss = shapes.rng(draw * 7919 + turn * 31 + h * 1000)
        local sigma, th, pts = 1e-2, math.rad(turn), {}
        for k = -80, 80 do
          local t = k * h * sigma
          local x, y = t, 0
          if t > 0 then x, y = t * math.cos(th), t * math.sin(th) end
          pts[#pts + 1] = { x + sigma * gauss(), y + sigma * gauss() }
        end
        local P = bs.points.new(pts)
        local pieces = bs.geom.segment(P, { closed = false, sigma = sigma })
        local at
        for i, p in ipairs(pieces) do if i > 1 and p.join == "corner" then at = i end end
        local soft = at and sharp.soften(P, pieces, at)
        if soft then
          local C = sharp.assemble(P, soft, { closed = false, sigma = sigma })
          bends = bends + 1
          if bs.geom.self_intersections(C, 4000) > 0 then loops = loops + 1 end
        end
      end
    end
  end
  print(("# %d softened corners: %d loops"):format(bends, loops))
  T.ok(bends >= 160, ("%d of 180 corners found and softened"):format(bends))
  T.ok(loops <= 12, ("%d of %d bends loop"):format(loops, bends))
end)

-- A scanner's shadow at every corner: dense sections whose primitives are sampled evenly over
-- [b, 1 - b] only (5% and 10% of each side bare at both ends), noise 1e-4 and 1e-3 of the
-- size, every outline with corners: 88 sections. Two runs shorter than the bare stretch
-- between them are each a position and a direction to one cubic, which bends through the
-- stretch: a corner's evidence window must reach past it (twice the gap between its
-- samples, segment_evidence.c). Before, it reached 32 sigma: right angles of a T of 300
-- samples per side read evidence 2 to 9 and were softened into bends that bulged 6 times
-- the floor out; 46 of these sections were within the floor and 39 had every corner, then
-- 76 and 70, 82 and 77 with dense line runs counted by their span, 83 and 78 with arcs'
-- runs tried up to where the next run ends, 87 and 80 with softened bends that do not loop.
local BARE_FLOOR = { within = 84, corners = 78 }

T.test("dense noisy sections with the ends of every side bare: corners confirmed across the gap", function()
  local n, within, all_corners = 0, 0, 0
  for k, name in ipairs(shapes.names()) do
    local o = shapes.all()[name]
    local size = shapes.size(o)
    for _, per in ipairs(#o.corners > 0 and { 100, 300 } or {}) do
      for j, rel in ipairs { 1e-4, 1e-3 } do
        for _, bare in ipairs { 0.05, 0.1 } do
          local pts = shapes.sample(o, per, { sigma = rel * size, seed = 100 * k + per + j, bare = bare })
          local what = ("%s %d per side noise %g, %g of each side bare"):format(name, per, rel, bare)
          local ok, C, rep = pcall(auto.run, bs.points.new(pts))
          T.ok(ok, what .. ": " .. tostring(ok or C))
          if ok then
            T.eq((bs.geom.self_intersections(C, 2000)), 0, what .. ": self-intersection")
            local ratio = shapes.hausdorff(bs, C, o, 2000, 60) / (3 * rel * size + 1e-3 * size)
            local f = shapes.features_found(o, pts, rep.pieces)
            n = n + 1
            if ratio <= 1 then within = within + 1 end
            if f.corners_ok >= #o.corners then all_corners = all_corners + 1 end
          end
        end
      end
    end
  end
  print(("# %d sections with bare ends: %d within the floor, %d with every corner within a sample")
        :format(n, within, all_corners))
  T.eq(n, 88, "sections run")
  T.ok(within >= BARE_FLOOR.within, ("%d sections within the floor"):format(within))
  T.ok(all_corners >= BARE_FLOOR.corners, ("%d sections with every corner"):format(all_corners))
end)

-- bs.geom.segment of a dense noisy section: the cover found on every k-th sample and moved
-- onto all of them (segment_dense.c) is a cover of every sample (two pieces share at most
-- a sample at each join), and no line or arc is left with
-- fewer than 2 samples; and bs.geom.segment_sigma, reading 500 of them, finds the noise.
T.test("dense noisy sections: every sample in a piece, none of too few; the noise of 500 samples", function()
  local n, near = 0, 0
  for c in shapes.sweep_cases { pers = { 60, 100, 300 }, unevens = { false }, thin = true } do
    local P = bs.points.new(c.pts)
    local what = ("%s %d per side noise %g"):format(c.name, c.per, c.rel)
    local pieces = bs.geom.segment(P, { closed = true, sigma = c.sigma })
    local held, m = {}, #P
    for i, p in ipairs(pieces) do
      T.ok(p.kind == "free" or p.count >= 2, ("%s: %s %d holds %d samples"):format(what, p.kind, i, p.count))
      for j = 0, p.count - 1 do
        local s = (p.first - 1 + j) % m + 1
        held[s] = (held[s] or 0) + 1
      end
    end
    local missed, shared = 0, 0
    for s = 1, m do
      if not held[s] then missed = missed + 1 elseif held[s] > 1 then shared = shared + 1 end
    end
    T.eq(missed, 0, what .. ": samples in no piece")
    T.ok(shared <= #pieces, ("%s: %d samples in two pieces"):format(what, shared))
    local s = bs.geom.segment_sigma(P, { closed = true })
    n = n + 1
    if math.abs(s / c.sigma - 1) <= 0.2 then near = near + 1 end
  end
  print(("# segment_sigma within 20%% of the true noise on %d of %d dense sections"):format(near, n))
  T.ok(near >= (shapes.thinned and 0.80 or 0.85) * n, ("segment_sigma within 20%% on %d of %d"):format(near, n))
end)

-- A dense section's cover is found on every k-th sample and each boundary then placed among
-- the samples around it; a line must still hold the distinct samples it needs there (steps
-- longer than the tolerance, or tolerances spanned end to end: bs.geom.segment's rule).
-- Before, a boundary could leave a line of 5 crowded samples spanning a fifth of the
-- tolerance, at 75 degrees across a serif T's straight side (300 uneven samples per side at
-- noise 1e-4): its curve zig-zagged there and crossed itself.
T.test("dense noisy sections: each line holds samples that fix its direction", function()
  local bad, lines = {}, 0
  for c in shapes.sweep_cases { pers = { 100, 300 }, unevens = { true }, thin = true } do
    local P = bs.points.new(c.pts)
    local tol = 4 * c.sigma
    for i, p in ipairs(bs.geom.segment(P, { closed = true, sigma = c.sigma })) do
      if p.kind == "line" then
        lines = lines + 1
        local long, m = 0, #P
        local x0, y0 = P:get(p.first)
        local x1, y1 = P:get((p.first + p.count - 2) % m + 1)
        for j = 1, p.count - 1 do
          local ax, ay = P:get((p.first + j - 2) % m + 1)
          local bx, by = P:get((p.first + j - 1) % m + 1)
          if math.sqrt((bx - ax) ^ 2 + (by - ay) ^ 2) > tol then long = long + 1 end
        end
        if long < 2 and math.sqrt((x1 - x0) ^ 2 + (y1 - y0) ^ 2) < 2 * tol then
          bad[#bad + 1] = ("%s %d per side noise %g: line %d"):format(c.name, c.per, c.rel, i)
        end
      end
    end
  end
  T.ok(lines >= (shapes.thinned and 200 or 500), ("%d lines looked at"):format(lines))
  T.eq(#bad, 0, table.concat(bad, "; "))
end)

-- Every line and arc bs.geom.segment returns is fitted to its samples: a dense cover's arc
-- moved onto every sample of a straight side (a gear's, an H's, a serif L's at 100 samples
-- per side) could fail its circle fit there and came out an arc with max = inf (its model
-- undefined, its curve far off: the pieces refused or wrong). Now such an arc is the line
-- of its samples (a free run where no line fits either).
T.test("dense noisy sections: every line and arc is fitted (a finite max)", function()
  local bad, models = {}, 0
  for c in shapes.sweep_cases { pers = { 100 }, thin = true } do
    local P = bs.points.new(c.pts)
    local s = bs.geom.segment_sigma(P, { closed = true })
    for i, p in ipairs(s > 0 and bs.geom.segment(P, { closed = true, sigma = s }) or {}) do
      if p.kind ~= "free" then models = models + 1 end
      if p.kind ~= "free" and not (p.max < math.huge and p.rms < math.huge) then
        bad[#bad + 1] = ("%s %d per side noise %g %s: %s %d, max %g"):format(c.name, c.per, c.rel,
          c.uneven and "uneven" or "even", p.kind, i, p.max)
      end
    end
  end
  T.ok(models >= (shapes.thinned and 200 or 500), ("%d lines and arcs looked at"):format(models))
  T.eq(#bad, 0, table.concat(bad, "; "))
end)

-- A large open section whose samples crowd closer than the noise takes its parameters along
-- anchors found on its subsample (every 3rd of 12000 samples here): the last samples past the
-- subsample's last had none, and the fit raised "11999 parameters for 12000 points".
T.test("an open section of 12000 crowded noisy samples: every sample has a parameter", function()
  for c in shapes.sweep_cases { names = { "gear", "T" }, pers = { 300 }, rels = { 1e-4 }, unevens = { true } } do
    local ok, C, rep = pcall(auto.run, bs.points.new(c.pts), { closed = false })
    T.ok(ok, c.name .. ": " .. tostring(ok or C))
    if ok then T.ok(rep.closed == false and rep.max < math.huge, c.name .. ": fitted open, finite") end
  end
end)

-- Noisy smooth shapes, noise up to 1e-2 of their size, four draws (96 sections): a corner's
-- evidence window is local (at most a tenth of the size; at 1e-2, 32 sigma is a third of
-- it). When runs sampled more densely than the noise were first let hold lines and arcs,
-- ellipses of 200 and 1500 samples read their tips as lines with corners of evidence 64 to
-- 262 against one cubic over half the ellipse (3 of these sections) until the window was
-- bounded.
T.test("noisy smooth shapes at noise to 1e-2: no corner", function()
  local names = {}
  for k in pairs(synth.smooth) do names[#names + 1] = k end
  table.sort(names)
  for draw = 1, 4 do
    for _, name in ipairs(names) do
      for _, m in ipairs { 200, 600, 1500 } do
        for _, rel in ipairs { 3e-3, 1e-2 } do
          local P = synth.noisy(synth.sample_smooth(synth.smooth[name], m, draw % 2 == 0), 2.5 * rel,
                                1000 * draw + m)
          local _, rep = auto.run(P)
          local what = ("%s, %d samples, noise %g, draw %d"):format(name, m, rel, draw)
          T.eq(synth.corners_of(rep), 0, what .. ": corners")
        end
      end
    end
  end
end)

T.test("dense noisy smooth shapes stay one smooth curve: no pieces, no corner", function()
  local shapes_smooth, names = synth.smooth_shapes()
  local n, read_as_pieces = 0, 0
  for _, name in ipairs(names) do
    for i, m in ipairs { 600, 1500, 4000 } do
      for j, rel in ipairs { 1e-4, 1e-3, 3e-3 } do
        local P = synth.noisy(synth.sample_smooth(shapes_smooth[name], m, (i + j) % 2 == 0), 2.5 * rel,
                              100 * i + j)
        local _, rep = auto.run(P)
        local what = ("%s, %d samples, noise %g"):format(name, m, rel)
        T.eq(synth.corners_of(rep), 0, what .. ": corners")
        if rep.pieces then
          print(("# %s: %d tangent lines and arcs"):format(what, #rep.pieces))
          read_as_pieces = read_as_pieces + 1
        end
        n = n + 1
      end
    end
  end
  T.ok(n >= 45, ("%d smooth sections"):format(n))
  T.ok(read_as_pieces <= 2, ("%d of %d read as tangent lines and arcs"):format(read_as_pieces, n))
end)
