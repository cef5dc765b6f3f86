-- test_sharp_noisy.lua: the auto strategy on sparse and noisy sections of lines and arcs
-- (issue 14), against the true outlines of tests/lua/shapes_sharp.lua, and on smooth shapes
-- (no corner where there is none).
--
-- Every section of the sweep (3 to 10 samples per side, noise 1e-4 to 3e-3 of the size,
-- even and uneven) is held to: no error, decided closed, no self-intersection, a finite
-- report. The issue's numbers (Hausdorff distance to the truth within 3 sigma + 1e-3 of
-- the size, corners within one sample, radii within 2%) are measured on every section,
-- smooth path or pieces, printed per density and noise, and held to the shares reached
-- (docs/auto.md lists them with those before this work): a change that loses sections
-- fails here. At noise 1e-2: no loop and no corner farther than a sample from a true one.
local T = require "tap"
local bs = require "bsfit"
local shapes = require "shapes_sharp"
local synth = require "synth"
local auto = require "bsfit.strategy.auto"

local dist, corner_places, spacing = shapes.dist, shapes.corner_places, shapes.spacing
local ALL, NAMES = shapes.all(), shapes.names()

-- One section (a case of shapes.sweep_cases): its checks that must hold, and what it
-- measures. Returns {pieces, within (Hausdorff), ratio, corners_ok, corners, radii_ok, radii}.
-- G1 as drawn: the largest turn at a tangent join between lines and arcs (degrees) and how
-- many joins may turn by more than KINK degrees (the arc is held to its neighbour's tangent
-- where that keeps it near its model; a chain of tangent arcs keeps one such join). Before,
-- 11 of 210 joins turned by more than 0.1 degrees, two by 175 and 177 (a line into a
-- circle running back along it, read as tangent: a cusp).
local KINK, KINKS, KINK_MAX = 0.1, 1, 1.0

local function run_case(c)
  local name, per, rel, uneven, seed = c.name, c.per, c.rel, c.uneven, c.seed
  local o, pts = c.o, c.pts
  local what = ("%s %d per side noise %g %s seed %d"):format(name, per, rel,
                                                             uneven and "uneven" or "even", seed)
  local ok, C, rep = pcall(auto.run, bs.points.new(pts))
  T.ok(ok, what .. ": " .. tostring(ok or C))
  if not ok then return nil end
  -- closed, or the doubt said (samples spread unevenly can leave a gap as long as a side)
  T.ok(rep.closed or rep.closed_ambiguous, what .. ": fitted open without a word")
  T.ok(rep.max == rep.max and rep.max < math.huge, what .. ": finite report")
  T.eq((bs.geom.self_intersections(C, 2000)), 0, what .. ": self-intersection")
  local r = { pieces = rep.pieces ~= nil, ratio = shapes.floor_ratio(bs, C, c), closed = rep.closed,
              corners = 0, corners_ok = 0, radii = 0, radii_ok = 0 }
  r.within = r.ratio <= 1
  local found = shapes.features_found(o, pts, rep.pieces)
  for k, v in pairs(found) do r[k] = v end
  r.kink, r.kinks, r.joins, r.opposed = shapes.tangent_kinks(C, rep, KINK)
  -- every arc reports the circle drawn: its ends and the curve at the middle of its range
  -- lie on it (a non-fillet arc reported its fitted circle, which its drawn ends lie within
  -- the tolerance of only: up to 31 sigma off on the sweep, 5 of its 270 arcs by more than
  -- 3); every piece's rms and max are its samples' distances to the curve (a free run's
  -- were 0, a softened bend's missing, an arc's to its fitted circle)
  local a, b = C:domain()
  for i, p in ipairs(rep.pieces or {}) do
    if p.kind == "arc" then
      local mid = { C:eval(a + (b - a) * (p.range[1] + p.range[2]) / 2) }
      for _, x in ipairs { p.start, p["end"], mid } do
        T.ok(math.abs(dist(x, p.centre) - p.radius) <= 1e-9 * c.size,
             ("%s: arc %d drawn %.3g off the circle it reports"):format(what, i, math.abs(dist(x, p.centre) - p.radius)))
      end
    end
    T.ok(p.rms and p.max, ("%s: piece %d (%s) reports no rms or max"):format(what, i, p.kind))
    if p.count > 0 and p.rms and p.max then
      local q2, worst = 0, 0
      for k = 0, p.count - 1 do
        local x = pts[(p.first - 1 + k) % #pts + 1]
        local _, d = C:closest(x[1], x[2])
        q2, worst = q2 + d * d, math.max(worst, d)
      end
      T.ok(math.abs(worst - p.max) <= 1e-7 * c.size and math.abs(math.sqrt(q2 / p.count) - p.rms) <= 1e-7 * c.size,
           ("%s: %s %d reports max %.6g rms %.6g, its samples %.6g %.6g"):format(what, p.kind, i, p.max,
             p.rms, worst, math.sqrt(q2 / p.count)))
    end
  end
  T.eq(r.opposed, 0, what .. ": a tangent join whose pieces run opposite ways (a cusp)")
  return r
end

-- the shares reached (of 390 sections; docs/auto.md, "Noisy and sparse sections")
-- (269 and 212 since an arc whose circle fit fails on its samples is their line and the
-- loop check samples closer to the corners, which sent a keyhole of 3 samples per side at
-- noise 1e-4 whose pieces crossed themselves to the smooth path; 218, 267, 210 before an
-- arc's run was tried up to where the next run ends; 217, 266, 209
-- before a join beyond an arc was read round its circle; 207, 260, 199 before the noise
-- search tried the levels below its start; 203, 252, 193, 1762 of 1770 and 123 of 149
-- before the pieces took over where the smooth curve missed its samples by 6 sigma (218,
-- 269, 212: a D of 10 uneven samples per side 55 times the floor off); before two lines
-- continued each other; 193 within with bs.geom.segment's
-- parameter count alone (param_cost math.huge); 180, 211, 169, 1567 of 1578 and 89 of 114
-- before the noise search's finer levels, softened weak corners, fillets that claim their
-- samples and pieces weighed by their residuals; before this work 82 within, 95 through
-- the pieces)
-- (227 before two lines meeting in a stretch no sample saw kept their corner instead of a
-- bend; 234, 277, 226 before an arc that meets neither way round a corner was tried as
-- its two lines, segment_corner_arcs.c; 237, 279, 230 before pieces refused at the noise
-- search's level were tried at the next two levels, noisy_pieces.find)
-- (241, 288, 234 and radii 147 of 179 within 2% before a fillet was made where its samples
-- fix its radius to less than 1%, its samples taken from the lines first, segment_fillets.c)
-- (251, 294, 245 before pieces a screen test refused at a noise that agreed were taken,
-- leniently, where the smooth curve missed a sample by 6 times that noise: pieces_path.lua
-- pieces_for_misfit; radii 172 of 217 within 2% then, 174 of 222 since)
-- Radii: within 2% where the samples fix them to 1% (radius_se), within 3 radius_se (or
-- 2%) elsewhere; of all, the share within 2%. (Since a fillet's radius_se counts its
-- lines' errors, not its own samples' as a free circle: 111 of 115 arcs fixed to 1%, for 88
-- of 92, and 86 of 102 others within 3 of it, for 109 of 125 under the wider one.)
-- (252, 299, 246 before pieces refused at the noise level and the two above were tried one
-- level below it where they show a strong corner, noisy_pieces.find)
-- (253, 301, 247 and radii 173 of 219 within 2%, 87 of 104 uncertain ones within 3
-- radius_se, before two lines that meet nowhere between them were given the side between
-- them, segment_corner_arcs.c: the 5 arcs more are serif ends of two L's of 6 uneven samples
-- per side, at noise 1e-3 and 3e-3, which went through their pieces 2.7 and 4.3 times the
-- floor off, where the smooth path had been 13.4 and 4.4)
-- (254, 308, 248 and radii 173 of 224 within 2%, 87 of 109 uncertain ones within 3
-- radius_se, before corners between lines were tried as fillets, segment_corner_fillets.c
-- bsfit__fillet_corners: 46 arcs more are found, fillets of 3 to 8 samples whose radius
-- their samples fix to a few percent only, so the share of arcs found within 2% fell to
-- 175 of 270 and of the uncertain ones within 3 radius_se to 120 of 155 (the radius_se of a
-- fillet is that of its chosen samples; choosing them among 25 ways is not in it), while
-- the true arcs read within 2% went from 173 to 175 of 420, within 10% from 199 to 215)
-- true_arcs: of the outlines' 420 arcs, those an arc piece reads within 2%.
local FLOOR = { within = 257, pieces = 326, pieces_within = 252, corners = 0.99, radii = 0.64,
                radii_fixed = 0.95, radii_uncertain = 0.77, true_arcs = 175 }
-- the sanitizer build's third of the sweep (shapes.thinned): its own counts, measured
-- (its 28 arcs whose samples do not fix the radius to 1% include a serif of a T of 3
-- samples per side at noise 1e-3 read as one arc of 229 degrees, which came with the
-- lenient swap that took that T from 11 to 1.9 times the floor: 22 of 28 within 3
-- radius_se, 0.79; the full sweep's share is 89 of 107)
-- (radii 35 of 50 and 22 of 28 before the sides between lines that do not meet: the 2 arcs
-- more are an L's serif ends, above)
-- (69, 91, 67, radii 35 of 52 and 22 of 30 before fillets at corners: 72, 100, 70, 36 of 76
-- and 38 of 54 since; true arcs read within 2%, 35 and 36 of 140)
if shapes.thinned then
  FLOOR = { within = 72, pieces = 100, pieces_within = 70, corners = 0.99, radii = 0.47,
            radii_fixed = 0.95, radii_uncertain = 0.7, true_arcs = 36 }
end

T.test("sparse and noisy sections: no error, closed, no loop; the issue's numbers measured on all", function()
  local rows, tot = {}, { n = 0, pieces = 0, within = 0, pw = 0, c = 0, cok = 0, r = 0, rok = 0,
                         rf = 0, rfok = 0, ruok = 0, ta = 0, taok = 0,
                         joins = 0, kinks = 0, kink = 0 }
  for c in shapes.sweep_cases { thin = true } do
    local r = run_case(c)
    local key = ("%2d per side, noise %g"):format(c.per, c.rel)
    local row = rows[key] or { n = 0, pieces = 0, within = 0, worst = 0 }
    rows[key] = row
    if r then
      row.n, tot.n = row.n + 1, tot.n + 1
      if r.pieces then row.pieces, tot.pieces = row.pieces + 1, tot.pieces + 1 end
      if r.within then row.within, tot.within = row.within + 1, tot.within + 1 end
      if r.within and r.pieces then tot.pw = tot.pw + 1 end
      row.worst = math.max(row.worst, r.ratio)
      tot.c, tot.cok = tot.c + r.corners, tot.cok + r.corners_ok
      tot.r, tot.rok = tot.r + r.radii, tot.rok + r.radii_ok
      tot.rf, tot.rfok = tot.rf + r.radii_fixed, tot.rfok + r.radii_fixed_ok
      tot.ruok = tot.ruok + r.radii_uncertain_ok
      tot.ta, tot.taok = tot.ta + r.true_arcs, tot.taok + r.true_arcs_ok
      tot.joins, tot.kinks = tot.joins + r.joins, tot.kinks + r.kinks
      tot.kink = math.max(tot.kink, r.kink)
    end
  end
  local keys = {}
  for key in pairs(rows) do keys[#keys + 1] = key end
  table.sort(keys)
  for _, key in ipairs(keys) do
    local row = rows[key]
    print(("# %s: %d sections, %d through the pieces, %d within 3 sigma + 1e-3, worst %.3g x")
      :format(key, row.n, row.pieces, row.within, row.worst))
  end
  print(("# all: %d sections, %d through the pieces (%d of them within), %d within; corners %d/%d "
         .. "within a sample, radii %d/%d within 2%%"):format(tot.n, tot.pieces, tot.pw, tot.within,
         tot.cok, tot.c, tot.rok, tot.r))
  T.ok(tot.within >= FLOOR.within, ("%d sections within the Hausdorff floor"):format(tot.within))
  T.ok(tot.pieces >= FLOOR.pieces, ("%d sections through the pieces"):format(tot.pieces))
  T.ok(tot.pw >= FLOOR.pieces_within, ("%d through the pieces and within"):format(tot.pw))
  T.ok(tot.cok >= FLOOR.corners * tot.c, ("corners within a sample: %d of %d"):format(tot.cok, tot.c))
  print(("# radii the samples fix to 1%%: %d of %d within 2%%; the others: %d of %d within 2%% or 3 radius_se")
    :format(tot.rfok, tot.rf, tot.ruok, tot.r - tot.rf))
  print(("# true arcs read as arcs within 2%%: %d of %d"):format(tot.taok, tot.ta))
  T.ok(tot.taok >= FLOOR.true_arcs, ("true arcs read within 2%%: %d of %d"):format(tot.taok, tot.ta))
  T.ok(tot.rok >= FLOOR.radii * tot.r, ("radii within 2%%: %d of %d"):format(tot.rok, tot.r))
  T.ok(tot.rfok >= FLOOR.radii_fixed * tot.rf,
       ("radii the samples fix to 1%%, within 2%%: %d of %d"):format(tot.rfok, tot.rf))
  T.ok(tot.ruok >= FLOOR.radii_uncertain * (tot.r - tot.rf),
       ("other radii within 3 radius_se: %d of %d"):format(tot.ruok, tot.r - tot.rf))
  print(("# tangent joins: %d, %d turn by more than %g degrees as drawn, the most %.3g")
    :format(tot.joins, tot.kinks, KINK, tot.kink))
  T.ok(tot.kinks <= KINKS, ("%d tangent joins turn by more than %g degrees"):format(tot.kinks, KINK))
  T.ok(tot.kink <= KINK_MAX, ("a tangent join turns by %.3g degrees"):format(tot.kink))
end)

-- Letters with serifs and stems on seeds of their own: a serif's two short noisy sides
-- were read as one arc whose circle met neither neighbour, and the section lost its
-- pieces to a bridge; that arc is now tried as the two lines of its corner
-- (segment_corner_arcs.c), and a weak corner between two steep lines is kept where the
-- bend that would soften it passes more than 3 sigma from it (noisy_pieces.lua). 41 of
-- these 96 sections were within the floor before the split, 44 with it and no such kept
-- corner, 45 before pieces refused at the noise search's level were tried at the next two.
local SERIF_FLOOR = { within = shapes.thinned and 16 or 46 } -- 16 of the sanitizers' 32
-- the sections of shapes.sweep_cases(opts) run through auto: no error, and at least
-- `floor` within the Hausdorff floor
local function within_at_least(opts, floor)
  local n, within = 0, 0
  for c in shapes.sweep_cases(opts) do
    local ok, C = pcall(auto.run, bs.points.new(c.pts))
    T.ok(ok, c.name .. ": " .. tostring(ok or C))
    n = n + 1
    if ok and shapes.floor_ratio(bs, C, c) <= 1 then within = within + 1 end
  end
  print(("# %d sections, %d within 3 sigma + 1e-3"):format(n, within))
  T.ok(within >= floor, ("%d of %d within the floor"):format(within, n))
end

T.test("letters with serifs on other seeds: a serif's arc across a corner split into its lines", function()
  within_at_least({ names = { "E", "H", "L_serif", "T_serif" }, pers = { 4, 5, 6 },
                    rels = { 1e-3, 3e-3 }, draws = 2, thin = true,
                    seed = function(k, per, j, d) return 31337 + 1000 * k + 10 * per + j + 7 * d end },
                  SERIF_FLOOR.within)
end)

-- A fillet made from a short line or an arc between two lines first takes the lines'
-- samples past its tangent points (segment_fillets.c, bsfit__settle_fillet); where the lines
-- refitted without them leave their tolerance or explain less, the fillet is tried as the
-- lines are. Without that second try a slot of 4 uneven samples per side at noise 1e-4
-- lost an end arc (10 times the floor off, 0.51 before). Slots, keyholes and D's on seeds
-- of their own: 106 of 144 within the floor without it.
local ENDS_FLOOR = { within = shapes.thinned and 37 or 109 } -- of 144, the sanitizers' 48
T.test("arcs at the ends of slots, keyholes and D's on seeds of their own", function()
  within_at_least({ names = { "slot", "keyhole", "D" }, pers = { 4, 5, 6 }, rels = { 1e-4, 1e-3 },
                    unevens = { true }, draws = 8, thin = true,
                    seed = function(k, per, j, d) return 5000 + 7919 * k + 97 * per + 13 * j + d end },
                  ENDS_FLOOR.within)
end)

-- Every line of bs.geom.segment runs from its start to its end along its reported tangent
-- (its model's direction). A line refitted after giving a fillet its samples kept its other
-- join where its old model met the neighbour's: 31 of 2741 lines of the sweep's sections
-- (segmented at the noise they show) left their direction, by up to 27 degrees. On two more
-- draws with seeds of their own (2026-12-07), 4 lines more: one after a free bridge (a
-- filleted pentagon of 10 samples per side at noise 3e-3, 0.13 degrees), and one whose
-- fillet then refused the refit and kept its join with it where the old line had been (a
-- slot of 5 per side at noise 3e-3, 0.45 degrees).
local function lines_off_tangent(cases)
  local lines, off, worst = 0, 0, 0
  for c in cases do
    local n, o, w = shapes.lines_off_tangent(shapes.segment_at_own_noise(bs, bs.points.new(c.pts), true))
    lines, off, worst = lines + n, off + #o, math.max(worst, w)
  end
  return lines, off, worst
end

T.test("lines run along their reported tangents", function()
  local lines, off, worst = lines_off_tangent(shapes.sweep_cases())
  print(("# %d lines, %d off their tangent, the most by sin %.3g"):format(lines, off, worst))
  T.ok(lines > 2000, ("%d lines"):format(lines))
  T.eq(off, 0, "lines off their reported tangent")
  for _, base in ipairs { 61000, 111000 } do
    lines, off, worst = lines_off_tangent(shapes.sweep_cases { draws = 2, thin = true,
      seed = function(k, per, j, d) return base + 1000 * k + 10 * per + j + 100000 * d end })
    print(("# seeds from %d: %d lines, %d off their tangent, the most by sin %.3g"):format(base, lines, off, worst))
    T.ok(lines > (shapes.thinned and 1000 or 4000), ("%d lines"):format(lines))
    T.eq(off, 0, ("seeds from %d: lines off their reported tangent"):format(base))
  end
end)

-- Open parts of the outlines (a quarter to a half of each dropped, at 3 to 30 samples per
-- side and noise 1e-4 to 1e-2): an open section's first line kept its start on its model
-- before a fillet's refit moved it, so it left its reported tangent (a part of a slot of 30
-- uneven samples per side at noise 3e-3, sin 7e-4); its ends are now placed again last.
T.test("open parts of outlines: lines run along their reported tangents", function()
  local uniform, all, names = shapes.rng(5), shapes.all(), shapes.names()
  local lines, off = 0, {}
  for k = 1, shapes.thinned and 300 or 900 do
    local name = names[1 + math.floor(#names * uniform())]
    local o = all[name]
    local rel = ({ 1e-4, 1e-3, 3e-3, 1e-2 })[1 + math.floor(4 * uniform())]
    local per = ({ 3, 4, 6, 10, 30 })[1 + math.floor(5 * uniform())]
    local pts = shapes.sample(o, per, { seed = k, sigma = rel * shapes.size(o), uneven = uniform() < 0.5 })
    local part = shapes.open_part(pts, uniform)
    local n, bad = shapes.lines_off_tangent(shapes.segment_at_own_noise(bs, bs.points.new(part), false))
    lines = lines + n
    for _, b in ipairs(bad) do
      off[#off + 1] = ("%s %d per side noise %g: sin %.3g"):format(name, per, rel, b.sin)
    end
  end
  print(("# %d lines of open parts, %d off their reported tangent"):format(lines, #off))
  T.ok(lines > (shapes.thinned and 500 or 1500), lines .. " lines")
  T.eq(#off, 0, "lines off their tangent: " .. table.concat(off, "; "))
end)

-- bs.geom.segment_sigma on sparse sections of lines and arcs, 3 to 6 samples per side: its
-- first guess (the chords' lower quartile) can fall on samples next to corners and arcs and
-- start the levels above the noise, where no level matches; the levels below the start are
-- then tried. 832 sections: 67 estimates of 0 and 635 within a factor 3 of the true noise
-- before, 44 and 652 after; a slot of 4 samples per side at noise 1e-4 started at 11 times
-- its noise and read 0 (sent down the smooth path, 7 times the floor off). 32 and 649
-- before an arc whose circle fit fails became the line of its samples, 40 and 647 after:
-- such an arc had counted its samples at residual 0, a pooled residual too low to be one.

T.test("the noise of the pieces when the first guess lies above it", function()
  local n, zero, good = 0, 0, 0
  for _, name in ipairs(NAMES) do
    local o = ALL[name]
    local size = shapes.size(o)
    for _, per in ipairs { 3, 4, 5, 6 } do
      for _, rel in ipairs { 1e-4, 1e-3 } do
        for seed = 1, 4 do
          for _, uneven in ipairs { false, true } do
            local sigma = rel * size
            local P = bs.points.new(shapes.sample(o, per, { sigma = sigma, seed = 7 * seed + per,
                                                            uneven = uneven }))
            local s = bs.geom.segment_sigma(P, { closed = true })
            n = n + 1
            if s == 0 then zero = zero + 1 elseif s >= sigma / 3 and s <= 3 * sigma then good = good + 1 end
          end
        end
      end
    end
  end
  print(("# segment_sigma: %d sections, %d estimates 0, %d within a factor 3"):format(n, zero, good))
  T.ok(zero <= 48 and good >= 645, ("%d estimates 0, %d within a factor 3 of %d"):format(zero, good, n))
  local o = ALL.slot
  local sigma = 1e-4 * shapes.size(o)
  local k
  for i, name in ipairs(NAMES) do if name == "slot" then k = i end end
  local P = bs.points.new(shapes.sample(o, 4, { sigma = sigma, seed = 1000 * k + 40 + 1 }))
  local s = bs.geom.segment_sigma(P, { closed = true })
  T.ok(s >= sigma / 2 and s <= 2 * sigma, ("slot of 4 per side: %g for noise %g"):format(s, sigma))
end)

-- A side with one sample a little past the tolerance (4 sigma) of its line is read as two
-- lines whose models do not meet between them; they continue each other, and their join is
-- kept (a short step) rather than sending the section down the smooth path, which rounds
-- every corner. Outlines of lines (and fillets), 6 to 10 samples per side, the longest side's
-- middle sample pushed out by 4.8 to 5.4 sigma: 87 of 144 within the floor before, 114 after.
T.test("a side split by one sample past the tolerance stays a side", function()
  local n, within = 0, 0
  for _, name in ipairs { "T", "L", "E", "H", "hexagon", "rrect" } do
    local o = ALL[name]
    local size, longest, k = shapes.size(o), 0, nil
    for j, q in ipairs(o.prims) do
      if q.kind == "line" and dist(q.a, q.b) > longest then longest, k = dist(q.a, q.b), j end
    end
    local q = o.prims[k]
    local nx, ny = (q.b[2] - q.a[2]) / longest, -(q.b[1] - q.a[1]) / longest
    for _, per in ipairs { 6, 8, 10 } do
      for _, rel in ipairs { 1e-4, 1e-3 } do
        for seed = 1, 4 do
          local sigma = rel * size
          local pts = shapes.sample(o, per, { sigma = sigma, seed = 100 * seed + per })
          local i, push = (k - 1) * per + per // 2, (4.6 + 0.2 * seed) * sigma
          pts[i] = { pts[i][1] + push * nx, pts[i][2] + push * ny }
          local C = auto.run(bs.points.new(pts))
          n = n + 1
          if shapes.hausdorff(bs, C, o, 2000, 60) <= 3 * sigma + 1e-3 * size then within = within + 1 end
        end
      end
    end
  end
  T.ok(within >= 110, ("split sides: %d of %d within 3 sigma + 1e-3"):format(within, n))
end)

T.test("noise 1e-2 of the size: no loop, no error, no corner farther than a sample from a true one "
       .. "(or from a fillet narrower than a step)", function()
  local far, corners = 0, 0
  local function seed(k, per) return 77 * k + per end
  for c in shapes.sweep_cases { pers = { 4, 6, 10 }, rels = { 1e-2 }, seed = seed } do
    local what = ("%s %d per side%s"):format(c.name, c.per, c.uneven and " uneven" or "")
    local ok, C, rep = pcall(auto.run, bs.points.new(c.pts))
    T.ok(ok, what .. ": " .. tostring(ok or C))
    if ok then
      T.eq((bs.geom.self_intersections(C, 2000)), 0, what .. ": self-intersection")
      local hs = spacing(c.pts)
      local places = corner_places(c.o, hs, c.sigma)
      for _, p in ipairs(rep.pieces or {}) do
        if p.join == "corner" then
          local best = math.huge
          for _, v in ipairs(places) do best = math.min(best, dist(v, p.start)) end
          corners = corners + 1
          if best > hs then far = far + 1 end
          T.ok(best <= hs, ("%s: corner (%g, %g) %g from a true one, spacing %g")
            :format(what, p.start[1], p.start[2], best, hs))
        end
      end
    end
  end
  print(("# noise 1e-2: %d corners found, %d farther than a sample"):format(corners, far))
end)

T.test("smooth shapes: no corner, no loop (24 to 200 points, noise 0 to 1e-2, even and uneven)", function()
  -- synth's circle, ellipse, star, superellipse and a cam
  local SMOOTH, names = synth.smooth_shapes()
  local false_corners = {}
  for _, name in ipairs(names) do
    for _, m in ipairs { 24, 40, 80, 200 } do
      for j, rel in ipairs { 0, 1e-4, 1e-3, 3e-3, 1e-2 } do
        for _, uneven in ipairs { false, true } do
          local P = synth.noisy(synth.sample_smooth(SMOOTH[name], m, uneven), 2.5 * rel, m + j)
          local what = ("%s %d points noise %g%s"):format(name, m, rel, uneven and " uneven" or "")
          local ok, C, rep = pcall(auto.run, P)
          T.ok(ok, what .. ": " .. tostring(ok or C))
          if ok then synth.check_smooth(T, C, rep, what, false_corners) end
        end
      end
    end
  end
  print(("# smooth shapes: %d of 200 with a corner: %s"):format(#false_corners,
                                                             table.concat(false_corners, ", ")))
  -- (an ellipse of 24 samples at noise 1e-2 had two arcs meeting at the ends of its major
  -- axis until the corner evidence also tried a regular parametric cubic over at most 45
  -- degrees of each arc)
  T.eq(#false_corners, 0, "smooth sections with a corner")
end)

-- A corner's evidence window is local: at most a tenth of the section's size
-- (segment_evidence.c). At noise 1e-2 of the size the dense window of 32 sigma spans a
-- third of it: an ellipse of 40 samples (draw 1) read a corner where an arc met a line
-- across its tip, one cubic over half the ellipse being the smooth alternative.
T.test("ellipses at noise 1e-2, 24 to 80 points, eight draws: no corner", function()
  for draw = 1, 8 do
    for _, m in ipairs { 24, 40, 60, 80 } do
      for _, uneven in ipairs { false, true } do
        local P = synth.noisy(synth.sample_smooth(synth.smooth.ellipse, m, uneven), 2.5e-2, 1000 * draw + m + 4)
        local _, rep = auto.run(P)
        local what = ("ellipse %d points%s draw %d"):format(m, uneven and " uneven" or "", draw)
        T.eq(synth.corners_of(rep), 0, what .. ": corners")
      end
    end
  end
end)

T.test("pieces that cannot make one curve keep the smooth path (a noisy cam raised in bs.curve.join)", function()
  -- 80 samples of the cam at noise 1e-2: segmented into one arc gone all the way round and a
  -- line of no length between its ends
  local P = synth.noisy(synth.sample_smooth(synth.cam, 80, false), 0.025, 1)
  local ok, C, rep = pcall(auto.run, P)
  T.ok(ok, tostring(ok or C))
  T.ok(ok and rep.pieces == nil and C:is_periodic(), "one smooth closed curve")
  local sharp = require "bsfit.strategy.sharp"
  -- pieces whose ends the join refuses (as bs.curve.join does when two parts do not meet):
  -- refused with the reason, and the smooth path taken, not an error out of auto.run
  -- (a T of 6 samples per side at noise 1e-3: through its 8 pieces otherwise)
  local Q = bs.points.new(shapes.sample(ALL.T, 6, { sigma = 1e-3 * shapes.size(ALL.T), seed = 1 }))
  local _, rep1 = auto.run(Q)
  T.eq(rep1.pieces and #rep1.pieces, 8, "the T through its pieces")
  local assemble = sharp.assemble
  sharp.assemble = function() error("bs.curve.join: part 2 starts 0.54 away from part 1's end") end
  local fine, C2, rep2 = pcall(auto.run, Q)
  sharp.assemble = assemble
  T.ok(fine, "a join refused: " .. tostring(fine or C2))
  T.ok(fine and rep2.pieces == nil and C2:is_periodic(), "a join refused: one smooth closed curve")
  T.ok(fine and tostring(rep2.pieces_rejected):find("make no curve", 1, true) ~= nil,
       "a join refused: said in rep.pieces_rejected (" .. tostring(fine and rep2.pieces_rejected) .. ")")
  T.ok(sharp.degenerate { { kind = "arc", start = { 1, 0 }, ["end"] = { 1, 0 }, radius = 1, sweep = 2 * math.pi },
                          { kind = "line", start = { 1, 0 }, ["end"] = { 1, 0 } } } ~= nil)
  T.eq(sharp.degenerate { { kind = "line", start = { 0, 0 }, ["end"] = { 1, 0 } },
                          { kind = "line", start = { 1, 0 }, ["end"] = { 0, 0 } } }, nil)
end)

T.test("an airfoil: corners only at its sharp trailing edge, none at the leading edge", function()
  for _, m in ipairs { 24, 40, 80, 200 } do
    for j, rel in ipairs { 0, 1e-4, 1e-3, 3e-3 } do
      for seed = 1, 2 do
        local P = synth.noisy(synth.airfoil(m), rel, 10 * m + 3 * j + seed)
        local what = ("airfoil %d points noise %g seed %d"):format(m, rel, seed)
        local C, rep = auto.run(P)
        for _, i in ipairs(rep.corners) do
          local x = P:get(i)
          T.ok(x > 0.8, ("%s: corner at x = %g"):format(what, x))
        end
        T.eq((bs.geom.self_intersections(C, 2000)), 0, what .. ": self-intersection")
      end
    end
  end
end)

-- The same section read from another first sample is the same section: where a closed
-- one is cut for the cover is chosen by geometry (the longest run, ties to the lowest
-- start in x), not by the samples' order (a filleted pentagon of 6 per side at noise 1e-4
-- was 1e-4 or 1.6e-2 of its size off by where its samples started).
T.test("the result does not depend on which sample a closed section starts at", function()
  for _, name in ipairs { "rrect", "hexagon", "pentagon", "slot", "keyhole", "D" } do
    local o = ALL[name]
    local size = shapes.size(o)
    for _, per in ipairs { 6, 10 } do
      for _, rel in ipairs { 1e-4, 1e-3 } do
        for seed = 1, 2 do
          local pts = shapes.sample(o, per, { sigma = rel * size, seed = seed })
          local what = ("%s %d per side noise %g seed %d"):format(name, per, rel, seed)
          local first_radii, first_C, first_path
          for shift = 0, #pts - 1, math.max(1, #pts // 5) do
            local q = {}
            for i = 1, #pts do q[i] = pts[(i - 1 + shift) % #pts + 1] end
            local C, rep = auto.run(bs.points.new(q))
            local radii = {}
            for _, p in ipairs(rep.pieces or {}) do
              if p.kind == "arc" then radii[#radii + 1] = p.radius end
            end
            table.sort(radii)
            local path = rep.pieces and "pieces" or "smooth"
            if not first_radii then
              first_radii, first_C, first_path = radii, C, path
            else
              T.eq(path, first_path, what .. ", from sample " .. shift + 1 .. ": path")
              T.eq(#radii, #first_radii, what .. ", from sample " .. shift + 1 .. ": arcs")
              for j = 1, math.min(#radii, #first_radii) do
                T.ok(math.abs(radii[j] - first_radii[j]) <= 1e-6 * first_radii[j],
                     ("%s, from sample %d: radius %g, %g from sample 1"):format(what, shift + 1,
                                                                          radii[j], first_radii[j]))
              end
              -- (the smooth path's periodic fit starts its parameter at the first sample:
              -- not the same curve to rounding, and not what this test is about; on the
              -- pieces, refits taken in the pieces' order can differ by 1e-6 of the size).
              -- The curves are compared, not their distances to the outline measured on
              -- 1000 samples each: those samples fall elsewhere on a curve whose parameter
              -- starts elsewhere, and read a filleted hexagon's two equal curves (2e-12
              -- apart) as 0.0340 and 0.0324 off.
              local h = path == "smooth" and 0 or select(2, first_C:closest_many(C:sample(2000))):max()
              T.ok(h <= 1e-4 * size,
                   ("%s, from sample %d: %g from the curve from sample 1"):format(what, shift + 1, h))
            end
          end
        end
      end
    end
  end
end)

-- A loop next to a corner can be far shorter than the step of the even samples the loop
-- check used to take (2000, or 32 per control point): the smooth fit of a gear of 3 samples
-- per side at noise 1e-4 crossed itself 3e-4 of the period past a corner, between two of
-- 2208 samples, and came out with rep.crossings 0. Of 1560 sparse sections (every outline,
-- 3 to 6 per side, three noise levels, ten seeds) six had such a hidden loop (serif T's,
-- gears, a rounded rectangle); these three outlines are held here. Each result is checked
-- with 40000 samples: evenly spread alone (the old check at that density) they found all
-- six; the check now also samples ever closer to the corners.
T.test("sparse noisy sections: no loop hidden between the loop check's samples", function()
  local hidden, n = {}, 0
  for _, name in ipairs { "T_serif", "gear", "rrect" } do
    local o = ALL[name]
    local size = shapes.size(o)
    for _, per in ipairs { 3, 4, 5, 6 } do
      for _, rel in ipairs { 1e-4, 1e-3, 3e-3 } do
        for seed = 1, 10 do
          local pts = shapes.sample(o, per, { sigma = rel * size, seed = 4242 + seed,
                                              uneven = seed % 2 == 0 })
          local C, rep = auto.run(bs.points.new(pts))
          n = n + 1
          if rep.crossings == 0 and bs.geom.self_intersections(C, 40000) > 0 then
            hidden[#hidden + 1] = ("%s %d per side noise %g seed %d"):format(name, per, rel, seed)
          end
        end
      end
    end
  end
  print(("# %d sections, %d with a loop the report does not give"):format(n, #hidden))
  T.eq(#hidden, 0, table.concat(hidden, "; "))
end)
