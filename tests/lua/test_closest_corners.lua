-- test_closest_corners.lua: closest points near the corners of a curve (knots of
-- multiplicity p: C0), against an independent dense measure (the curve evaluated densely
-- span by span, the nearest evaluation refined by zooming in: no Newton, no sample
-- bracket). Newton from the nearest coarse sample used to cross a corner and stay on the
-- wrong side, or bracket a short span's sample too narrowly to reach the long span
-- beyond: 6% of the points near a corner came back up to 10 times too far.
local T = require "tap"
local bs = require "bsfit"
local synth = require "synth"

-- the distance from (x, y) to C over its distinct knots kn: 200 evaluations per span, then
-- 20 around the nearest, twelve times, each round a tenth as wide
local function dense(C, x, y, kn)
  local best = math.huge
  for s = 1, #kn - 1 do
    local a, b, lo, hi, n = kn[s], kn[s + 1], kn[s], kn[s + 1], 200
    if b > a then
      for _ = 1, 12 do
        local bt, bd = lo, math.huge
        for j = 0, n do
          local t = lo + (hi - lo) * j / n
          local px, py = C:eval(t)
          local dd = (px - x) ^ 2 + (py - y) ^ 2
          if dd < bd then bd, bt = dd, t end
        end
        best = math.min(best, bd)
        local h = (hi - lo) / n
        lo, hi, n = math.max(a, bt - h), math.min(b, bt + h), 20
      end
    end
  end
  return math.sqrt(best)
end

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

T.test("closest points near corners are the true ones (independent dense measure)", function()
  local points, off, worst = 0, 0, 0
  for seed = 1, 4 do
    local uniform, gauss = synth.rng(1000 + seed)
    for trial = 1, 300 do
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
  -- what remains (1 point in about 6000) is not a corner's: the coarse samples of a long
  -- span lie farther than another branch of the curve passing by, and the search starts
  -- on that branch
  T.ok(points > 4000, points .. " points")
  T.ok(off <= points // 1000, ("%d of %d points off the true distance (worst by %.3g)")
         :format(off, points, worst))
end)
