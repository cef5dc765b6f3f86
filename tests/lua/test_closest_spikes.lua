-- test_closest_spikes.lua: C:closest and C:closest_many return the global minimum of the
-- distance near thin spikes, hairpins and sliver spans, where the coarse samples of the
-- curve lie on the wrong branch. Generated curves: stars with very sharp tips, hairpins,
-- curves with C0 corners and sliver spans (two corner knots 1e-13 apart, as auto leaves
-- them); degree 1..5, rational and not, closed and open; points on both sides of a spike
-- and near its tip. Each answer is checked against mathematics: its distance is |C(t) - P|
-- (evaluated here), and it is not farther than an independent dense measure (every span
-- evaluated at 400 points, every local minimum of those refined by zooming in: actual
-- points of the curve, so an upper bound of the true distance) by more than the stated
-- tolerance (1e-9 of the distance plus 1e-13 of the curve's extent, with rounding).
local T = require "tap"
local bs = require "bsfit"
local synth = require "synth"

local measure = require "dense_distance"
local dist2, dense, distinct = measure.dist2, measure.distance, measure.distinct

local function weights(uniform, n, rational)
  if not rational then return nil end
  local w = {}
  for j = 1, n do w[j] = 0.3 + 2 * uniform() end
  return w
end

-- a closed star of k tips, each tip a control point far out between two close ones: the
-- spike is thin (its sides `gap` apart in angle), its tip sharp; the features are the
-- tips on the curve (the samples farthest out, locally)
local function star(uniform, p, rational)
  local k, cp = 3 + math.floor(uniform() * 5), {}
  local gap = 10 ^ (-2 - 3 * uniform())
  for i = 0, k - 1 do
    local a = 2 * math.pi * (i + 0.3 * uniform()) / k
    local r = 0.6 + 0.4 * uniform()
    cp[#cp + 1] = { r * math.cos(a - gap), r * math.sin(a - gap) }
    cp[#cp + 1] = { (3 + 2 * uniform()) * math.cos(a), (3 + 2 * uniform()) * math.sin(a) }
    cp[#cp + 1] = { r * math.cos(a + gap), r * math.sin(a + gap) }
  end
  local C = bs.curve.new { degree = p, control_points = cp, periodic = true,
                           weights = weights(uniform, #cp, rational) }
  local a, b = C:domain()
  local n, r, tips = 4000, {}, {}
  for j = 0, n - 1 do
    local x, y = C:eval(a + (b - a) * j / n)
    r[j] = { x * x + y * y, x, y }
  end
  for j = 0, n - 1 do
    local prev, next = r[(j - 1) % n][1], r[(j + 1) % n][1]
    if r[j][1] >= prev and r[j][1] > next and r[j][1] > 4 then
      tips[#tips + 1] = { r[j][2], r[j][3] }
    end
  end
  return C, #tips > 0 and tips or { cp[2] }
end

-- an open hairpin: out along a line and back `gap` beside it, the turn sharp
local function hairpin(uniform, p, rational)
  local gap, len, m = 10 ^ (-2 - 3 * uniform()), 2 + 2 * uniform(), 3 + math.floor(uniform() * 4)
  local cp = {}
  for j = 0, m do cp[#cp + 1] = { len * j / m, 0.05 * math.sin(j) } end
  for j = m, 0, -1 do cp[#cp + 1] = { len * j / m, 0.05 * math.sin(j) + gap } end
  local C = bs.curve.new { degree = p, control_points = cp,
                           weights = weights(uniform, #cp, rational) }
  return C, { { len, 0.05 * math.sin(m) + 0.5 * gap } }
end

-- an open curve with C0 corners (p equal knots) and a sliver span between two of them
-- (1e-13 apart), as auto leaves them; its control points random
local function sliver(uniform, p, rational)
  local K, inner = {}, {}
  for _ = 1, p + 1 do K[#K + 1] = 0 end
  local ni = 1 + math.floor(uniform() * 3)
  for i = 1, ni do inner[i] = (i - 0.5 + 0.4 * (uniform() - 0.5)) / ni end
  local corners = {}
  for i = 1, ni do
    local c = inner[i]
    for _ = 1, p do K[#K + 1] = c end
    if i == 1 then
      for _ = 1, p do K[#K + 1] = c + 1e-13 end
      corners[#corners + 1] = c + 1e-13
    end
    corners[#corners + 1] = c
  end
  for _ = 1, p + 1 do K[#K + 1] = 1 end
  local n, cp = #K - p - 1, {}
  for j = 1, n do cp[j] = { uniform() * 4, uniform() * 4 } end
  -- the sliver's piece (control points p+1 .. 2p+1) from the corner's point to 1e-7 of it:
  -- a short piece, as auto leaves between two corner knots
  for j = p + 2, 2 * p + 1 do
    cp[j] = { cp[p + 1][1] + 1e-7 * uniform(), cp[p + 1][2] + 1e-7 * uniform() }
  end
  local C = bs.curve.new { degree = p, knots = K, control_points = cp,
                           weights = weights(uniform, n, rational) }
  local at = {}
  for _, c in ipairs(corners) do at[#at + 1] = { C:eval(c) } end
  return C, at
end

local makers = { { "star", star }, { "hairpin", hairpin }, { "sliver", sliver } }

-- points near each feature (1e-8 .. 1 away, any direction: both sides of a spike, beyond
-- its tip) and a few anywhere near the curve
local function points_near(uniform, gauss, features, count)
  local P = {}
  for q = 1, count do
    local f = features[1 + (q - 1) % #features]
    local r = 10 ^ (-8 + 8 * uniform())
    P[#P + 1] = { f[1] + r * gauss(), f[2] + r * gauss() }
  end
  return P
end

local function extent(C)
  local lo, hi = { math.huge, math.huge }, { -math.huge, -math.huge }
  for i = 1, C:count() do
    local x, y = C:control_point(i)
    lo[1], hi[1] = math.min(lo[1], x), math.max(hi[1], x)
    lo[2], hi[2] = math.min(lo[2], y), math.max(hi[2], y)
  end
  return math.max(hi[1] - lo[1], hi[2] - lo[2])
end

-- under the sanitizers (BSFIT_SANITIZED, set by CMake) a third of the trials: the dense
-- measure runs in Lua, which they slow fivefold; the normal build runs them all
local TRIALS = T.thinned and 20 or 60

T.test("closest points near spikes, hairpins and slivers are the global ones", function()
  local stats, worst_ratio = {}, 0
  for seed = 1, 3 do
    local uniform, gauss = synth.rng(7000 + seed)
    for trial = 1, TRIALS do
      for _, maker in ipairs(makers) do
        local name, make = maker[1], maker[2]
        local p = 1 + (trial + seed) % 5
        local rational = trial % 2 == 0
        local C, features = make(uniform, p, rational)
        local K = C:knots():totable()
        local kn = distinct(K)
        local a, b = C:domain()
        local inside = {}
        for _, v in ipairs(kn) do
          if v >= a and v <= b then inside[#inside + 1] = v end
        end
        local ext, P = extent(C), points_near(uniform, gauss, features, 6)
        local pts = bs.points.new(P)
        local um, dm = C:closest_many(pts)
        local st = stats[name] or { points = 0, off = 0 }
        stats[name] = st
        for q, X in ipairs(P) do
          local t1, d1 = C:closest(X[1], X[2])
          local truth = dense(C, X[1], X[2], inside)
          T.ok(d1 == dm:get(q) and t1 == um:get(q), "closest and closest_many agree")
          local own = math.sqrt(dist2(C, t1, X[1], X[2]))
          T.ok(math.abs(own - d1) <= 1e-12 * (ext + d1), "the distance is |C(t) - P|")
          -- the rounding of the evaluation: a sliver piece's points are known to ulp(u) /
          -- 1e-13 of its size (1.4e-7 at most here), in the parameter's differences
          local tol = 1e-9 * truth + 1e-13 * ext + 1e-14 * (ext + truth)
                      + (name == "sliver" and 2e-10 or 0)
          if d1 > truth + tol then
            st.off = st.off + 1
            st.first = st.first or ("p=%d%s seed %d trial %d point %d: %.17g, dense %.17g")
              :format(p, rational and " rational" or "", seed, trial, q, d1, truth)
          end
          worst_ratio = math.max(worst_ratio, (d1 - truth) / (truth + ext))
          st.points = st.points + 1
        end
      end
    end
  end
  for _, maker in ipairs(makers) do
    local st = stats[maker[1]]
    print(("# %s: %d of %d off; first %s"):format(maker[1], st.off, st.points, st.first))
  end
  for _, maker in ipairs(makers) do
    local name, st = maker[1], stats[maker[1]]
    T.ok(st.points >= 1000 * TRIALS / 60, name .. ": " .. st.points .. " points")
    T.ok(st.off == 0, ("%s: %d of %d points farther than the dense measure; first: %s")
           :format(name, st.off, st.points, st.first))
  end
  print(("# worst (closest - dense) / (dense + extent): %.3g"):format(worst_ratio))
end)

T.test("closest points on curves of degree 0 and high degree, rational or not", function()
  local uniform, gauss = synth.rng(7100)
  local off, points = 0, 0
  for trial = 1, 40 do
    local p = ({ 0, 6, 9, 12 })[1 + trial % 4]
    local n = p + 1 + math.floor(uniform() * 6)
    local K = {}
    for _ = 1, p + 1 do K[#K + 1] = 0 end
    for i = 1, n - p - 1 do K[#K + 1] = i / (n - p) end
    for _ = 1, p + 1 do K[#K + 1] = 1 end
    if p == 0 then K[1] = 0; K[#K] = 1 end
    local cp = {}
    for j = 1, n do cp[j] = { uniform() * 4, uniform() * 4 } end
    local C = bs.curve.new { degree = p, knots = K, control_points = cp,
                             weights = weights(uniform, n, trial % 2 == 0) }
    local ext = extent(C)
    local P = {}
    for q = 1, 8 do P[q] = { 4 * uniform() + 0.1 * gauss(), 4 * uniform() } end
    local _, dm = C:closest_many(bs.points.new(P))
    for q, X in ipairs(P) do
      local t1, d1 = C:closest(X[1], X[2])
      local truth = dense(C, X[1], X[2], distinct(K))
      T.ok(d1 == dm:get(q), "closest and closest_many agree")
      T.ok(math.abs(math.sqrt(dist2(C, t1, X[1], X[2])) - d1) <= 1e-12 * (ext + d1),
           "the distance is |C(t) - P|")
      if d1 > truth + 1e-9 * truth + 1e-13 * ext + 1e-14 * (ext + truth) then off = off + 1 end
      points = points + 1
    end
  end
  T.ok(off == 0, ("%d of %d points farther than the dense measure"):format(off, points))
end)
