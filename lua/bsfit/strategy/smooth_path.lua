-- lua/bsfit/strategy/smooth_path.lua
-- The smooth path of the auto strategy: one smooth curve through a section that lines and
-- arcs do not explain (docs/auto.md, steps `params` to `fit`): parameters on anchors,
-- sharp corners as triple knots with the spans beside them wide enough to read the sides'
-- directions through the noise, the count search to the noise level (or to `tol`), the
-- final fit with parameter correction, and optional Huber reweighting.
--
--   local smooth = require "bsfit.strategy.smooth_path"
--   smooth.params(P, ctx); smooth.corners(P, ctx); smooth.count(P, ctx); smooth.fit(P, ctx)
--   smooth.reweight(P, ctx)                 -- robust = true
--   smooth.fit_corrected(ctx, P, n, rounds) -- one fit of n control points (the loops step)
--   smooth.count_range(P, ctx)              -- the counts the search may try

local bs = require "bsfit"
local common = require "bsfit.strategy.common"
local anchors = require "bsfit.strategy.anchors"

local M = {}

local function params_table(ctx)
  local c = ctx.cache.params_table
  if c and c.of == ctx.params then return c.t end
  local t = ctx.params:totable()
  ctx.cache.params_table = { of = ctx.params, t = t }
  return t
end

-- How far apart the samples with parameters in [a, b] lie (a span of a closed curve:
-- taken modulo 1, b may pass 1),
-- by the first and the last of them; 0 without two.
local function span_extent(P, u, a, b)
  local m = #u
  local len = b - a
  a = a % 1
  b = a + len
  local function first_at_least(x) -- first i with u[i] >= x, m + 1 if none
    local lo, hi = 1, m + 1
    while lo < hi do
      local mid = (lo + hi) // 2
      if u[mid] >= x then hi = mid else lo = mid + 1 end
    end
    return lo
  end
  local i1 = first_at_least(a)
  local i2 = b <= 1 and first_at_least(b) - 1 or first_at_least(b - 1) - 1
  if b <= 1 and (i1 > m or i2 < i1) then return 0 end
  if b > 1 then
    if i1 > m then i1 = 1; if i2 < 1 then return 0 end end
    if i2 < 1 then i2 = m end
  end
  if i1 == i2 then return 0 end
  local x, y = { P:get(i1) }, { P:get(i2) }
  local d2 = 0
  for k = 1, #x do d2 = d2 + (x[k] - y[k]) ^ 2 end
  return math.sqrt(d2)
end

-- The spans on either side of a corner must reach far enough along its sides for the
-- control points next to the corner, which set the sides' directions there, to be
-- read off more than noise: 3 sigma over the sine of half the corner's opening (a thin
-- trailing edge, open by 17 degrees, needs 20 sigma; a right angle 4 sigma). Where the
-- samples crowd at the corner (a densely sampled trailing edge), the averaging rule
-- puts the next knot within the noise of it, the two sides' control points swap sides
-- and the curve crosses over: such a knot is dropped (its spans merge).
local function widen_corner_spans(ctx, P, K, N)
  local turns, sigma, p = ctx.corner_turns, ctx.sigma, ctx.settings.degree
  local nb = #ctx.corners
  if nb == 0 or not (sigma and sigma > 0) then return K, N end
  local kv = K:totable()
  local u = params_table(ctx)
  if #u ~= #P then return K, N end
  -- distinct knots of the period (kv[1] is the first corner), with multiplicities
  local val, mult = {}, {}
  for i = 1, N do
    if #val > 0 and kv[i] - val[#val] <= 1e-14 then mult[#val] = mult[#val] + 1
    else val[#val + 1], mult[#val + 1] = kv[i], 1 end
  end
  local changed, c = false, 0
  local g = 1
  while g <= #val do
    if mult[g] >= p then
      c = c + 1
      local turn = math.rad(turns and turns[c] or 90)
      local need = 4 * sigma / math.max(math.sin(0.5 * (math.pi - turn)), 0.15)
      for _, dir in ipairs { 1, -1 } do
        while N > nb * p + 1 do
          local h = (g - 1 + dir) % #val + 1
          if mult[h] >= p then break end
          local a, b = val[g], val[h]
          if dir < 0 then a, b = b, val[g] end
          if b < a then b = b + 1 end
          if span_extent(P, u, a, b) >= need then break end
          mult[h] = mult[h] - 1
          N = N - 1
          changed = true
          if mult[h] == 0 then
            table.remove(val, h); table.remove(mult, h)
            if h < g then g = g - 1 end
          end
        end
      end
    end
    g = g + 1
  end
  if not changed then return K, N end
  local out = {}
  for i = 1, #val do for _ = 1, mult[i] do out[#out + 1] = val[i] end end
  out[#out + 1] = out[1] + 1
  return bs.vector.new(out), N
end

-- The knots for n control points: one period with triple knots at the corners
-- (closed), or clamped averaging knots (open), placed on the anchors' parameters when
-- there are anchors. Returns the knots and the count actually placed (the empty-span
-- guard may merge spans, widen_corner_spans drop knots).
local function knots_for(ctx, n)
  local p = ctx.settings.degree
  if ctx.anchors and not ctx.knot_params then -- the corners step was replaced
    anchors.knots(ctx, ctx.corner_positions or ctx.corners)
  end
  if common.closed(ctx) then n = math.max(n, #ctx.corners * p + 1) end -- each corner takes p knots
  -- Anchors too few to give n control points' spans two each (a sparse spiral whose
  -- windows read its curvature as noise, 4 sigma apart, left 5 anchors of 21 samples for
  -- 8 control points, and the knot placement raised): the knots go on the samples'
  -- parameters (the parameters keep the anchors).
  local u, breaks = ctx.knot_params, ctx.knot_breaks
  if not u or #u < 2 * n then u, breaks = ctx.params, nil end
  breaks = breaks or ctx.corner_positions or ctx.corners
  if common.closed(ctx) then
    if #breaks == 0 and #u >= 6 and #u < 12 then
      -- a handful of points without corners (6 samples of a D): the averaging rule
      -- around the period (the break placement's empty-span guard needs more points)
      return common.ok("knots", bs.knots.averaging { params = u, count = n, degree = p,
                                                     closed = true }), n
    end
    local K, N = common.ok("knots", bs.knots.breaks { params = u, degree = p, count = n,
      breaks = breaks })
    return widen_corner_spans(ctx, ctx.P, K, N)
  end
  return common.ok("knots", bs.knots.averaging { params = u, count = n, degree = p,
                                                 closed = false }), n
end

-- One fit with knots K on parameters u; reuses the strategy's fitter. Returns the
-- curve, or the fail triple of a numerical outcome (nil, message, code); misuse and bugs
-- raise.
local function try_fit(ctx, P, K, u, w)
  local o = { degree = ctx.settings.degree, knots = K, periodic = common.closed(ctx),
              solver = ctx.settings.solver }
  local F = ctx.cache.fitter
  if F then F:configure(o) else F = bs.fitter(o); ctx.cache.fitter = F end
  return F:fit(P, u, w)
end

-- The same, raising "fit failed: ..." on a numerical outcome.
local function fit_once(ctx, P, K, u, w)
  return common.ok("fit", try_fit(ctx, P, K, u, w))
end

-- Weighted RMS and maximum of the distances d (Vector) with weights w (Vector). With
-- `huber` (robust setting) a far point counts as if at distance huber, so the search is
-- not driven by outliers that the reweighting will discount.
local function stats(d, w, huber)
  local max, imax = d:max()
  return d:rms(w, huber or nil), max or 0, imax or 1
end

M.NEWTON = 4 -- Newton steps per foot point: the start is always close
local NEWTON = M.NEWTON

-- Fit with n control points, then `rounds` parameter corrections (each: project
-- the points on the curve, refit with the foot parameters). Returns the curve, the
-- foot parameters, the distances and the count placed. With `measure_sub`, the
-- distances are those of the subsample (large sections, count search).
function M.fit_corrected(ctx, P, n, rounds, measure_sub)
  local K, N = knots_for(ctx, n)
  local u, w = ctx.params, ctx.weights
  local sub = measure_sub and ctx.sub
  if sub then
    sub.u = sub.u or common.every(u, sub.stride)
    sub.w = sub.w or common.every(w, sub.stride)
  end
  -- a search fit of a large section: the subsample alone, while it has points to spare
  -- in every span (the count is read off statistics of 5000 points either way)
  if sub and rounds == 0 and N * 4 <= #sub.P then
    -- a subsample the knots leave a span without data fails numerically (the fail
    -- triple): then every point is fitted; anything else is a bug and raises
    local C = try_fit(ctx, sub.P, K, sub.u, sub.w)
    if C then
      local _, ds = C:project(sub.P, sub.u, NEWTON)
      return C, u, ds, N, sub.w, #sub.P
    end
  end
  local C = fit_once(ctx, P, K, u, w)
  local d
  for _ = 1, rounds do
    u = C:project(P, u, NEWTON)
    C = fit_once(ctx, P, K, u, w)
  end
  if sub then
    local su = u == ctx.params and sub.u or common.every(u, sub.stride)
    local _, ds = C:project(sub.P, su, NEWTON)
    return C, u, ds, N, sub.w, #P
  end
  u, d = C:project(P, u, NEWTON)
  return C, u, d, N, w, #P
end

-- Chord parameters over the trusted points (weight >= trust x median), on anchors where
-- samples crowd closer than the noise (bsfit.strategy.anchors).
function M.params(P, ctx)
  local u = anchors.params(P, ctx, nil, common.subsample(ctx, P))
  if u then return u end
  return common.ok("params", bs.params_trusted(P, ctx.settings.param, {
    closed = common.closed(ctx), weights = ctx.settings.point_weights, trust = ctx.settings.trust }))
end

-- Corners found on the subsample of a large section (idx: its 1-based indices, tt their
-- turns): placed at its points (the chords across are negligible there).
local function subsample_corners(P, ctx, sub, idx, tt)
  local full, forced, order = {}, {}, {}
  for i, k in ipairs(idx) do full[i] = (k - 1) * sub.stride + 1; forced[full[i]] = true; order[i] = i end
  table.sort(order, function(a, b) return full[a] < full[b] end)
  ctx.corner_turns = {}
  for i, k in ipairs(order) do ctx.corner_turns[i] = tt[k] end
  table.sort(full)
  ctx.corner_positions = full
  if ctx.anchors then ctx.params = anchors.params(P, ctx, forced, sub) or ctx.params end
  anchors.knots(ctx, full)
  return full
end

-- Sharp corners (bs.geom.corners) of a closed section of 12 points or more: their
-- 1-based samples; the parameters made to pass through those between samples, and the
-- knots' breaks placed on them.
function M.corners(P, ctx)
  if not common.closed(ctx) or #P < 12 then anchors.knots(ctx); return {} end
  local o = { closed = true }
  if ctx.sigma > 0 then o.sigma = ctx.sigma end
  local sub = common.subsample(ctx, P)
  local idx, turns, where, at = bs.geom.corners(sub and sub.P or P, o)
  common.ok("corners", idx, turns, where)
  if #idx == 0 then anchors.knots(ctx); return {} end
  local m = #P
  local tt = turns:totable()
  if sub then return subsample_corners(P, ctx, sub, idx, tt) end
  -- positions in increasing order (the first corner's may wrap to just below m + 1),
  -- with their corner points, so the parameters can be made to agree with them
  local order, pos, pts = {}, where:totable(), at:totable()
  for i = 1, #pos do order[i] = i end
  table.sort(order, function(a, b) return pos[a] < pos[b] end)
  local spos, spts = {}, {}
  ctx.corner_turns = {}
  for i, k in ipairs(order) do spos[i], spts[i], ctx.corner_turns[i] = pos[k], pts[k], tt[k] end
  ctx.corner_positions = spos
  -- The parameters are made to pass through the corners that lie between two samples
  -- further apart than the noise: closer samples measure the noise, not the corner
  -- they straddle (a densely sampled trailing edge), and the corner is among them.
  local far, fpos, fpts = {}, {}, {}
  for i, x in ipairs(spos) do
    local j = math.floor(x)
    if x > j then
      local a, b = { P:get(j) }, { P:get(j % m + 1) }
      local d2 = 0
      for k = 1, #a do d2 = d2 + (a[k] - b[k]) ^ 2 end
      if d2 >= (anchors.ANCHOR * ctx.sigma) ^ 2 then
        far[#far + 1] = j
        fpos[#fpos + 1], fpts[#fpts + 1] = x, spts[i]
      end
    end
  end
  if ctx.anchors and #far > 0 then
    -- the samples on either side of each such corner become anchors, so that the
    -- corner's chord is one the corner parameters can stretch
    local forced = {}
    for _, j in ipairs(far) do forced[j] = true; forced[j % m + 1] = true end
    ctx.params = anchors.params(P, ctx, forced, common.subsample(ctx, P)) or ctx.params
  end
  if #fpos > 0 then
    ctx.params = common.ok("corner parameters", bs.params_through_corners(P, ctx.params,
      bs.vector.new(fpos), bs.points.new(fpts), ctx.settings.param, { closed = true }))
  end
  anchors.knots(ctx, spos)
  return common.as_table(idx)
end


function M.count_range(P, ctx)
  local m, p = #P, ctx.settings.degree
  local nmin = math.max(p + 1, common.closed(ctx) and (#ctx.corners * p + 4) or 0, math.min(8, m // 2))
  -- small sections may use as many as the paper's 50% rule; large ones a third,
  -- at most 4000 (a noisy section stops far below, at its noise level)
  local nmax = ctx.settings.count_max or math.min(m <= 500 and m // 2 or m // 3, 4000)
  nmax = math.max(math.min(nmax, m), nmin)
  -- every span holds two anchors at least (the guard of the knot placement)
  if ctx.knot_params then nmax = math.max(math.min(nmax, #ctx.knot_params // 2), nmin) end
  return math.min(nmin, nmax), nmax
end

-- Count search. Without tol: grow the count until the weighted RMS distance is at
-- the noise level (what a least-squares fit of the truth would leave:
-- sigma sqrt(1 - n/m)); past it, keep growing only while each step still cuts the
-- RMS by 30% (clean data, where the estimate is only the model's own bias; on
-- noisy data the RMS then barely moves). Within 1.5 sigma of it, stop as soon as a
-- step takes less than 2 sigma^2 per added control point off the residual sum of
-- squares (Akaike's rule: fitting noise takes sigma^2) and keep the fit before. If the
-- noise level is never reached, stop when two steps in a row improve less than 2% on
-- the best fit (knots move with the count, so more is not always better) and keep the
-- best. With tol: grow until the maximum distance is at most tol.
local function size_of(P)
  local m, b, size = #P, { P:get(1) }, 0
  for i = 2, m, math.max(1, m // 64) do
    local q, dd = { P:get(i) }, 0
    for k = 1, #b do dd = dd + (q[k] - b[k]) ^ 2 end
    size = math.max(size, math.sqrt(dd))
  end
  return size
end

-- The weights the count search measures its fits by: the trusted points' own, the others
-- 0 (a gross outlier of weight 1e-2 a tenth of the size off outweighs the noise of a
-- hundred samples, and the search would add control points to reach it). w: the weights
-- of all points, or of every stride-th (a large section's subsample).
local function measure_weights(ctx, w, stride)
  local t = common.trusted(ctx)
  if not t then return w end
  ctx.cache.measure_weights = ctx.cache.measure_weights or {}
  local c = ctx.cache.measure_weights[stride]
  if c and c.of == w then return c.w end
  local v = w:copy()
  for _, i in ipairs(t.out) do
    if (i - 1) % stride == 0 then v:set((i - 1) // stride + 1, 0) end
  end
  ctx.cache.measure_weights[stride] = { of = w, w = v }
  return v
end

function M.count(P, ctx)
  local m = #P
  local n, nmax = M.count_range(P, ctx)
  local tol, sigma = ctx.settings.tol, ctx.sigma
  local floor = 1e-7 * size_of(P) -- clean data: no need to go below a relative 1e-7
  local tries, best, chosen, stalls, prev = {}, nil, nil, 0, nil
  while true do
    local C, u, d, N, wm, mfit = M.fit_corrected(ctx, P, n, ctx.sub and 0 or 1, ctx.sub ~= nil)
    wm = measure_weights(ctx, wm, #wm == #P and 1 or ctx.sub.stride)
    local rms, max = stats(d, wm, ctx.settings.robust and ctx.settings.huber * math.max(sigma, 1e-12))
    local fit = { curve = C, params = u, distances = d, count = N, rms = rms, max = max,
                  rss = #d * rms * rms }
    tries[#tries + 1] = { count = N, rms = rms, max = max }
    local score = tol and max or rms
    if best and score >= 0.98 * (tol and best.max or best.rms) then stalls = stalls + 1 else stalls = 0 end
    if best == nil or score < (tol and best.max or best.rms) then best = fit end
    if tol then
      if max <= tol then chosen = fit; break end
    elseif chosen then
      if rms < 0.7 * chosen.rms and rms > floor then chosen = fit else break end
    elseif rms <= 1.05 * math.max(sigma * math.sqrt(math.max(0.25, 1 - N / mfit)), floor) then
      chosen = fit
    elseif prev and sigma > 0 and N > prev.count and rms <= 1.5 * sigma and
           prev.rss - fit.rss < 2 * sigma * sigma * (N - prev.count) * #d / mfit then
      -- The added control points bought no more than fitting noise does (each takes
      -- about sigma^2 off the residual sum of squares; the rule asks for twice that,
      -- as Akaike's criterion does): the shape is followed. Without this, a noise
      -- estimate a few percent low is never reached and the count runs to its cap,
      -- following the noise.
      chosen = prev
      break
    end
    prev = fit
    if n >= nmax or (not chosen and stalls >= 2) then break end
    n = math.min(nmax, math.max(n + 1, math.floor(n * 1.3 + 0.5)))
  end
  ctx.tries, ctx.search = tries, chosen or best
  return ctx.search.count
end

-- Final fit: the count found, `correct` rounds of parameter correction.
function M.fit(P, ctx)
  -- on large sections one correction round does nearly all the good (and each costs a
  -- projection of every point)
  local rounds = ctx.settings.correct
  if ctx.sub then rounds = math.min(rounds, 1) end
  local C, u, d = M.fit_corrected(ctx, P, ctx.count, rounds)
  ctx.params_final, ctx.distances, ctx.distances_of = u, d, C
  return C
end

-- Optional Huber reweighting: points farther than huber x sigma from the curve get
-- weight w c/|d|; three rounds.
function M.reweight(P, ctx)
  local c = ctx.settings.huber * math.max(ctx.sigma, 1e-12)
  local base = ctx.weights:totable()
  local C, u, d = ctx.curve, ctx.params_final, ctx.distances
  for _ = 1, 3 do
    local dt, w = d:totable(), {}
    for i = 1, #dt do w[i] = dt[i] > c and base[i] * c / dt[i] or base[i] end
    local K = knots_for(ctx, ctx.count)
    C = fit_once(ctx, P, K, u, bs.vector.new(w))
    u, d = C:project(P, u, NEWTON)
    ctx.robust_weights = w
  end
  ctx.params_final, ctx.distances, ctx.distances_of = u, d, C
  return C
end

return M
