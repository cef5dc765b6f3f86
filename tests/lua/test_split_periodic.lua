-- test_split_periodic.lua: cutting a periodic curve open (C:split) at the period start,
-- at every knot, an ulp beside them and anywhere else gives one open curve over one
-- period with no span narrower than the original's (a cut at u + T rounded an ulp past
-- the knot one period on used to leave a span one ulp wide), tracing the same points.
local T = require "tap"
local bs = require "bsfit"
local synth = require "synth"

-- a random periodic curve: degree p, N distinct control points, knots starting at an
-- offset of any scale with spans of uneven scales, rational when asked
local function random_curve(uniform, p, N, rational)
  local k = { (uniform() - 0.5) * 10 ^ math.floor(uniform() * 6 - 2) }
  for i = 1, N do k[i + 1] = k[i] + (0.05 + uniform()) * 10 ^ math.floor(uniform() * 3 - 1) end
  local cp, w = {}, {}
  for i = 1, N do
    cp[i] = { uniform() * 10 - 5, uniform() * 10 - 5 }
    w[i] = 0.5 + uniform()
  end
  return bs.curve.new { degree = p, periodic = true, knots = k, control_points = cp,
                        weights = rational and w or nil }, k
end

-- the spacing of doubles at x (Lua has no math.ulp)
local function ulp(x)
  x = math.abs(x)
  if x < 2 ^ -1021 then return 2 ^ -1074 end
  local e = math.floor(math.log(x, 2))
  while 2 ^ e > x do e = e - 1 end
  while 2 ^ (e + 1) <= x do e = e + 1 end
  return 2 ^ (e - 52)
end

local function min_span(K)
  local h = math.huge
  for i = 1, #K - 1 do
    if K[i + 1] > K[i] then h = math.min(h, K[i + 1] - K[i]) end
  end
  return h
end

-- the open piece L traces C from t over one period: 40 parameters compared
local function same_trace(C, L, t, period, size)
  local a = L:domain()
  for j = 0, 39 do
    local s = period * j / 40
    local x1, y1 = C:eval(t + s)
    local x2, y2 = L:eval(math.max(a, math.min(a + s, select(2, L:domain()))))
    if math.abs(x1 - x2) > 1e-9 * size or math.abs(y1 - y2) > 1e-9 * size then return false end
  end
  return true
end

T.test("a periodic curve cut at its knots has no sliver span and the same trace", function()
  local uniform = synth.rng(2024)
  local cuts, curves = 0, 0
  for trial = 1, 300 do
    local p = 1 + trial % 5
    local N = p + 1 + math.floor(uniform() * 8)
    local C, k = random_curve(uniform, p, N, trial % 3 == 0)
    local period = k[#k] - k[1]
    local narrowest = min_span(C:knots():totable())
    curves = curves + 1
    -- at every knot of the period (its start and end included) and 2 ulps either side:
    -- no span of the piece narrower than half the curve's narrowest
    local at = {}
    for j = 1, #k do
      at[#at + 1] = k[j]
      at[#at + 1] = k[j] + 2 * ulp(k[j])
      at[#at + 1] = k[j] - 2 * ulp(k[j])
    end
    for _, t in ipairs(at) do
      local L = C:split(t)
      local h = min_span(L:knots():totable())
      T.ok(h >= 0.5 * narrowest, ("degree %d, N %d, cut at %.17g: a span %.3g wide (the "
           .. "curve's narrowest %.3g)"):format(p, N, t, h, narrowest))
      local a, b = L:domain()
      T.ok(math.abs((b - a) - period) <= 1e-12 * (math.abs(a) + period), "one period")
      T.ok(same_trace(C, L, t, period, 10),
           ("degree %d, cut at %.17g: the same trace"):format(p, t))
      cuts = cuts + 1
    end
    -- anywhere: the same trace
    local t = k[1] + uniform() * period
    T.ok(same_trace(C, C:split(t), t, period, 10), ("degree %d, cut at %.17g"):format(p, t))
  end
  T.ok(curves == 300 and cuts > 3000, ("%d curves, %d cuts"):format(curves, cuts))
end)
