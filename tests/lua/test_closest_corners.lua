-- test_closest_corners.lua: closest points near the corners of a curve (knots of
-- multiplicity p: C0), against an independent dense measure (the curve evaluated densely
-- span by span, the nearest evaluation refined by zooming in: no Newton, no sample
-- bracket; every local minimum of the dense scan refined). Newton from the nearest coarse
-- sample used to cross a corner and stay on the
-- wrong side, or bracket a short span's sample too narrowly to reach the long span
-- beyond: 6% of the points near a corner came back up to 10 times too far.
local T = require "tap"
local bs = require "bsfit"
local synth = require "synth"

-- the independent dense measure (tests/lua/dense_distance.lua)
local dense = require("dense_distance").distance

-- a random open curve of degree p with one corner (p equal knots) and sometimes a double
-- knot elsewhere, polynomial or rational; returns it, the corner and the distinct knots
local function cornered_curve(uniform, p, rational)
  local ni = p + math.floor(uniform() * 5)
  local inner = {}
  for i = 1, ni do inner[i] = uniform() end
  table.sort(inner)
  local K, corner, i = {}, nil, 1
  for _ = 1, p + 1 do K[#K + 1] = 0 end
  while i <= ni do
    if not corner and i + p - 1 <= ni and (uniform() < 0.5 or i + p - 1 == ni) then
      corner = inner[i]
      for _ = 1, p do K[#K + 1] = corner end
      i = i + p
    else
      K[#K + 1] = inner[i]
      if p >= 3 and uniform() < 0.2 then K[#K + 1] = inner[i] end -- a double knot: C1
      i = i + 1
    end
  end
  for _ = 1, p + 1 do K[#K + 1] = 1 end
  local n, cp, w = #K - p - 1, {}, {}
  for j = 1, n do
    cp[j] = { uniform() * 4, uniform() * 4 }
    w[j] = 0.3 + 2 * uniform()
  end
  local kn = {}
  for _, v in ipairs(K) do
    if kn[#kn] ~= v then kn[#kn + 1] = v end
  end
  return bs.curve.new { degree = p, knots = K, control_points = cp,
                        weights = rational and w or nil }, corner, kn
end

-- under the sanitizers (BSFIT_SANITIZED, set by CMake) a third of the trials: the dense
-- measure runs in Lua, which they slow fivefold; the normal build runs them all
local TRIALS = T.thinned and 100 or 300

T.test("closest points near corners are the true ones (independent dense measure)", function()
  local points, off, worst = 0, 0, 0
  for seed = 1, 4 do
    local uniform, gauss = synth.rng(1000 + seed)
    for trial = 1, TRIALS do
      local p = 2 + trial % 3
      local C, corner, kn = cornered_curve(uniform, p, trial % 2 == 0)
      if corner then
        local cx, cy = C:eval(corner)
        local batch = {}
        for q = 1, 10 do
          -- 1e-5 .. 1e-2 from the corner, in a curve about 4 across
          local r = 10 ^ (-2 - 3 * uniform())
          batch[q] = { cx + 0.3 * r * gauss(), cy + 0.3 * r * gauss() }
        end
        local _, dm = C:closest_many(bs.points.new(batch))
        for q, P in ipairs(batch) do
          local _, d1 = C:closest(P[1], P[2])
          local truth = dense(C, P[1], P[2], kn)
          T.ok(d1 == dm:get(q), "closest and closest_many agree")
          T.ok(d1 >= truth - 1e-12, "no closer than the curve: the dense measure is a bound")
          points = points + 1
          if d1 > truth + 1e-9 * (1 + truth) then
            off = off + 1
            worst = math.max(worst, d1 - truth)
          end
        end
      end
    end
  end
  -- none remains: the global stage (closest_pieces.c) also finds the foot when the coarse
  -- samples of a long span lie farther than another branch of the curve passing by (1
  -- point in about 6000 before it)
  T.ok(points > 4000 * TRIALS / 300, points .. " points")
  T.ok(off == 0, ("%d of %d points off the true distance (worst by %.3g)")
         :format(off, points, worst))
end)

-- {======================================================================
-- The distances of auto's deviation report on the sharp path (bs.geom.piece_distances)
-- =======================================================================

local shapes = require "shapes_sharp"
local auto = require "bsfit.strategy.auto"

-- What the report measured before the loop moved to C (the reference): Newton from each
-- sample's place in its own piece's range (a repeated sample from its first's), and the
-- global closest point; the nearer.
local function lua_distances(C, P, pieces)
  local a, b = C:domain()
  local m, u = #P, {}
  for _, p in ipairs(pieces) do
    for k = 0, p.count - 1 do
      local f = (k + 0.5) / p.count
      u[(p.first - 1 + k) % m + 1] = a + (b - a) * (p.range[1] + f * (p.range[2] - p.range[1]))
    end
  end
  for i = 1, m do u[i] = u[i] or a end
  for i = 2, m do
    local x0, y0 = P:get(i - 1)
    local x1, y1 = P:get(i)
    if x0 == x1 and y0 == y1 then u[i] = u[i - 1] end
  end
  local _, d = C:project(P, bs.vector.new(u), 8)
  local _, g = C:closest_many(P)
  local t = {}
  for i = 1, m do t[i] = math.min(d:get(i), g:get(i)) end
  return t
end

-- the distinct knots of C inside its domain (the dense measure's spans)
local function domain_knots(C)
  local a, b = C:domain()
  local kn = { a }
  for _, v in ipairs(C:knots():totable()) do
    if v > kn[#kn] and v < b then kn[#kn + 1] = v end
  end
  kn[#kn + 1] = b
  return kn
end

-- sections of lines and arcs, exact and noisy, even and uneven, a sample repeated now and then
local function sharp_cases(per_list, sigmas)
  local out = {}
  for name, o in pairs(shapes.all()) do
    for _, per in ipairs(per_list) do
      for _, rel in ipairs(sigmas) do
        for uneven = 0, 1 do
          local pts = shapes.sample(o, per, { uneven = uneven == 1, seed = per * 7 + uneven,
                                              sigma = rel * shapes.size(o) })
          if per % 2 == 1 then table.insert(pts, 3, { pts[2][1], pts[2][2] }) end
          out[#out + 1] = { name = ("%s per %d noise %g%s"):format(name, per, rel,
                                                                   uneven == 1 and " uneven" or ""),
                            P = bs.points.new(pts) }
        end
      end
    end
  end
  table.sort(out, function(x, y) return x.name < y.name end)
  return out
end

-- Samples on straight spans that no other span comes near take the smaller of Newton's
-- distance from their own piece and the distance to the span's line (certified: see
-- src/core/piece_distances.c); the others the nearer of Newton's and the global search's,
-- as the Lua loop did. The certified ones differ from the loop's in the last digits only
-- (the same foot, by other arithmetic), never by more than 1e-14 of the size above it.
-- Samples on arcs are certified from their span's circle without Newton: below the loop's
-- by up to 1e-12 of the size, where the loop's Newton on a rational span stops short along
-- the tangent (a rounded rectangle of 9 uneven samples per side: 7.8e-12 by the loop's
-- foot, 5.3e-14 by a golden-section search along the span, 0 by the circle; the sample is
-- on the true outline). The dense measure below holds both to the truth.
T.test("piece distances: the C kernel agrees with the Lua loop to rounding", function()
  local cases, n, differ, worst, worst_max = 0, 0, 0, 0, 0
  for _, c in ipairs(sharp_cases({ 3, 4, 6, 9 }, { 0, 1e-4, 1e-3 })) do
    local C, rep = auto.run(c.P)
    if rep.pieces then
      local d = bs.geom.piece_distances(C, c.P, rep.pieces, 8)
      local ref = lua_distances(C, c.P, rep.pieces)
      local size, ok, mx, mref = shapes.size(shapes.all()[c.name:match("^%S+")]), #d == #ref, 0, 0
      for i = 1, #ref do
        local e = d:get(i) - ref[i]
        ok = ok and e <= 1e-14 * size and e >= -1e-12 * size
        if e ~= 0 then differ = differ + 1 end
        worst = math.max(worst, math.abs(e) / size)
        mx, mref = math.max(mx, d:get(i)), math.max(mref, ref[i])
      end
      worst_max = math.max(worst_max, (mx - mref) / size)
      T.ok(ok, c.name .. ": the same distances to rounding")
      cases, n = cases + 1, n + #ref
    end
  end
  print(("# %d sections, %d samples: %d differ, by at most %.3g of the size; the largest "
         .. "distance up by %.3g at most"):format(cases, n, differ, worst, worst_max))
  T.ok(cases >= 60, cases .. " sections of pieces, " .. n .. " samples")
  T.ok(worst_max <= 1e-14, "the reported maximum moves by rounding at most: " .. worst_max)
end)

-- Points near the curve given to the wrong pieces (their Newton search starts on the wrong
-- side of a corner, of a thin slot, of a gear): the certificate must refuse them, and their
-- distance is then never worse than the global search's (which misses, in about one point
-- in a few hundred placed this far off, where a long span's coarse samples lie farther than
-- another branch passing by: tested above), nor nearer than the curve.
T.test("piece distances: points given to the wrong pieces", function()
  local uniform, gauss = synth.rng(77)
  local outlines = shapes.all()
  outlines.thin = shapes.filleted { { 0, 0 }, { 10, 0 }, { 10, 0.02 }, { 0, 0.02 } }
  outlines.comb = shapes.filleted { { 0, 0 }, { 6, 0 }, { 6, 3 }, { 5, 3 }, { 5, 0.05 },
                                    { 4.95, 0.05 }, { 4.95, 3 }, { 0, 3 } }
  local checked, off, global_off, worse = 0, 0, 0, 0
  for _, name in ipairs { "thin", "comb", "gear", "T_serif", "keyhole", "D" } do
    local o = outlines[name]
    local P = bs.points.new(shapes.sample(o, 5))
    local C, rep = auto.run(P)
    T.ok(rep.pieces ~= nil, name .. ": pieces")
    local size, m, Q = shapes.size(o), #P, {}
    for i = 1, m do
      local x, y = P:get(math.floor(uniform() * m) + 1)
      local r = size * 10 ^ (-6 + 5 * uniform())
      Q[i] = { x + r * gauss(), y + r * gauss() }
    end
    local QP = bs.points.new(Q)
    local d, kn = bs.geom.piece_distances(C, QP, rep.pieces, 8), domain_knots(C)
    local _, g = C:closest_many(QP)
    for i = 1, m, 2 do
      local truth, lim = dense(C, Q[i][1], Q[i][2], kn), 1e-9 * size
      T.ok(d:get(i) >= truth - 1e-12, "no closer than the curve")
      if d:get(i) > g:get(i) + 1e-14 * size then worse = worse + 1 end
      if d:get(i) > truth + lim then off = off + 1 end
      if g:get(i) > truth + lim then global_off = global_off + 1 end
      checked = checked + 1
    end
  end
  T.ok(checked > 150, checked .. " points")
  T.ok(worse == 0, worse .. " points farther than the global search puts them")
  T.ok(off <= global_off, ("%d of %d points off the true distance, the global search %d")
         :format(off, checked, global_off))
end)

T.test("piece distances are the true distances (independent dense measure)", function()
  local checked, off, worst = 0, 0, 0
  for _, c in ipairs(sharp_cases({ 4 }, { 0, 1e-3 })) do
    local C, rep = auto.run(c.P)
    if rep.pieces then
      local d, kn = bs.geom.piece_distances(C, c.P, rep.pieces, 8), domain_knots(C)
      for i = 1, #c.P, 3 do
        local x, y = c.P:get(i)
        local truth = dense(C, x, y, kn)
        T.ok(d:get(i) >= truth - 1e-12, "no closer than the curve")
        checked = checked + 1
        if d:get(i) > truth + 1e-9 * (1 + truth) then
          off, worst = off + 1, math.max(worst, d:get(i) - truth)
        end
      end
    end
  end
  print("# " .. checked .. " checked"); T.ok(checked > 300, checked .. " samples")
  T.ok(off == 0, ("%d of %d samples off the true distance (worst by %.3g)")
         :format(off, checked, worst))
end)

T.test("piece distances: bad pieces are errors naming the piece and field", function()
  local P = bs.points.new { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } }
  local C = bs.curve.line({ 0, 0 }, { 1, 0 })
  local ok, err = pcall(bs.geom.piece_distances, C, P,
                        { { first = 5, count = 1, range = { 0, 1 } } })
  T.ok(not ok and err:find("piece 1: field 'first'", 1, true), tostring(err))
  ok, err = pcall(bs.geom.piece_distances, C, P, { { first = 1, count = 2, range = { 0 } } })
  T.ok(not ok and err:find("piece 1: field 'range'", 1, true), tostring(err))
  ok, err = pcall(bs.geom.piece_distances, C, P, { { first = 1, count = 2, range = { 0, 1 } },
                                                 { first = 2, count = -1, range = { 0, 1 } } })
  T.ok(not ok and err:find("piece 2: field 'count'", 1, true), tostring(err))
  ok, err = pcall(bs.geom.piece_distances, C, P, { { first = 1, count = 4, range = { 0, 0 / 0 } } })
  T.ok(not ok and err:find("piece 1", 1, true), tostring(err))
  local d = bs.geom.piece_distances(C, P, { { first = 1, count = 4, range = { 0, 1 } } })
  T.ok(math.abs(d:get(3) - 1) < 1e-15 and d:get(1) == 0, "distances to the segment")
end)
