-- lua/bsfit/strategy/auto.lua
-- The default strategy (beyond the paper): reads the noise level off the data,
-- grows the control-point count until the curve follows the shape but not the
-- noise, keeps sharp corners sharp, corrects the parameters to foot points, and
-- never lets a down-weighted point distort its neighbours.
--
--   local auto = require "bsfit.strategy.auto"
--   local C, rep = auto.run(P, {point_weights = w})
--
-- Steps (each replaceable by name, like every strategy: a function f(P, ctx) or a
-- plain value, e.g. {count = 24} or {corners = {}}):
--   params   chord parameters over the trusted points (weight >= trust x median);
--            the others interpolated (bs.params_trusted)
--   sigma    noise level normal to the curve, from the data alone (bs.geom.noise_sigma)
--   weights  the file's weights (point_weights), else 1
--   corners  sharp corners (bs.geom.corners); a triple knot is put at each
--   count    the search: counts grow geometrically from a small start, each fit's
--            parameters corrected once, until the weighted RMS distance reaches the
--            noise level (or stops improving near it); `tol` asks for a maximum
--            distance instead
--   fit      the final fit: `correct` rounds of parameter correction (foot points)
--   reweight optional Huber reweighting, run when the setting robust = true (a step
--            and a setting cannot share a name: opts[step] replaces the step)
--   measure  distances of the points to the curve (vectorised projection in C)
-- Settings: degree (3), param ("chord"), closed (true), trust (0.1), correct (3),
-- robust (false), huber (1.345), count_max (m/2 up to 500 points, then m/3, at
-- most 4000); optional:
-- point_weights, tol.
-- rep: count, sigma, corners (1-based indices), tries ({count, rms, max} per fit of
-- the search), rms, max, max_index, residuals (distances), times per step.

local bs = require "bsfit"
local common = require "bsfit.strategy.common"

local M = { name = "auto" }

M.settings = { degree = 3, param = "chord", closed = true, trust = 0.1, correct = 3,
               robust = false, huber = 1.345 }
M.optional = { point_weights = true, tol = true, count_max = true }

M.order = { "params", "sigma", "weights", "corners", "count", "fit", "reweight", "measure" }

local steps = {}
M.steps = steps

-- {======================================================================
-- Helpers
-- =======================================================================

local function as_table(v)
  if v == nil then return {} end
  if type(v) == "table" then return v end
  return v:totable()
end

local function closed(ctx) return common.closed(ctx) end

-- The knots for n control points: one period with triple knots at the corners
-- (closed), or clamped averaging knots (open). Returns the knots and the count
-- actually placed (the empty-span guard may merge spans).
local function knots_for(ctx, n)
  local p = ctx.settings.degree
  if closed(ctx) then
    n = math.max(n, #ctx.corners * p + 1) -- each corner takes p knots
    local K, N = common.ok("knots", bs.knots.breaks { params = ctx.params, degree = p, count = n,
                                                      breaks = ctx.corner_positions or ctx.corners })
    return K, N
  end
  return common.ok("knots", bs.knots.averaging { params = ctx.params, count = n, degree = p,
                                                 closed = false }), n
end

-- One fit with knots K on parameters u; reuses the strategy's fitter.
local function fit_once(ctx, P, K, u, w)
  local o = { degree = ctx.settings.degree, knots = K, periodic = closed(ctx) }
  local F = ctx.cache.fitter
  if F then F:configure(o) else F = bs.fitter(o); ctx.cache.fitter = F end
  return common.ok("fit", F:fit(P, u, w))
end

-- Weighted RMS and maximum of the distances d (Vector) with weights w (Vector). With
-- `huber` (robust setting) a far point counts as if at distance huber, so the search is
-- not driven by outliers that the reweighting will discount.
local function stats(d, w, huber)
  local max, imax = d:max()
  return d:rms(w, huber or nil), max or 0, imax or 1
end

-- Large sections are read through a subsample of at most SUBSAMPLE points for the
-- noise level, the corners and the distances measured during the count search:
-- all three are local or statistical, and the fits themselves still use every point.
local SUBSAMPLE = 5000

-- ctx.sub = {P = Points, stride = s, u = its parameters (set later)} when #P > SUBSAMPLE
local function subsample(ctx, P)
  if ctx.sub ~= nil or #P <= SUBSAMPLE then return ctx.sub end
  local s = math.ceil(#P / SUBSAMPLE)
  local t = {}
  for i = 1, #P, s do t[#t + 1] = { P:get(i) } end
  ctx.sub = { P = bs.points.new(t), stride = s }
  return ctx.sub
end

-- every s-th value of a Vector, as a Vector
local function every(v, s)
  local t, r = v:totable(), {}
  for i = 1, #t, s do r[#r + 1] = t[i] end
  return bs.vector.new(r)
end

local NEWTON = 4 -- Newton steps per foot point: the start is always close

-- Fit with n control points, then `rounds` parameter corrections (each: project
-- the points on the curve, refit with the foot parameters). Returns the curve, the
-- foot parameters, the distances and the count placed. With `measure_sub`, the
-- distances are those of the subsample (large sections, count search).
local function fit_corrected(ctx, P, n, rounds, measure_sub)
  local K, N = knots_for(ctx, n)
  local u, w = ctx.params, ctx.weights
  local sub = measure_sub and ctx.sub
  if sub then
    sub.u = sub.u or every(u, sub.stride)
    sub.w = sub.w or every(w, sub.stride)
  end
  -- a search fit of a large section: the subsample alone, while it has points to spare
  -- in every span (the count is read off statistics of 5000 points either way)
  if sub and rounds == 0 and N * 4 <= #sub.P then
    local ok, C = pcall(fit_once, ctx, sub.P, K, sub.u, sub.w)
    if ok then
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
    local su = u == ctx.params and sub.u or every(u, sub.stride)
    local _, ds = C:project(sub.P, su, NEWTON)
    return C, u, ds, N, sub.w, #P
  end
  u, d = C:project(P, u, NEWTON)
  return C, u, d, N, w, #P
end

-- }======================================================================

-- {======================================================================
-- Steps
-- =======================================================================

function steps.params(P, ctx)
  return common.ok("params", bs.params_trusted(P, ctx.settings.param, {
    closed = closed(ctx), weights = ctx.settings.point_weights, trust = ctx.settings.trust }))
end

function steps.sigma(P, ctx)
  if #P < 6 then return 0 end
  local sub = subsample(ctx, P)
  return common.ok("noise estimate", bs.geom.noise_sigma(sub and sub.P or P, { closed = closed(ctx) }))
end

function steps.weights(P, ctx)
  local pw = ctx.settings.point_weights
  if pw == nil then return bs.weights.uniform(P) end
  if type(pw) == "table" then pw = bs.vector.new(pw) end
  if #pw ~= #P then error(("auto: point_weights has %d values for %d points"):format(#pw, #P), 0) end
  return pw
end

function steps.corners(P, ctx)
  if not closed(ctx) or #P < 12 then return {} end
  local o = { closed = true }
  if ctx.sigma > 0 then o.sigma = ctx.sigma end
  local sub = subsample(ctx, P)
  local idx, turns, where, at = bs.geom.corners(sub and sub.P or P, o)
  common.ok("corners", idx, turns, where)
  if #idx == 0 then return {} end
  if sub then
    -- found on the subsample: at its points (the chords across are negligible there)
    local full = {}
    for i, k in ipairs(idx) do full[i] = (k - 1) * sub.stride + 1 end
    table.sort(full)
    ctx.corner_positions = full
    return full
  end
  -- positions in increasing order (the first corner's may wrap to just below m + 1),
  -- with their corner points, so the parameters can be made to agree with them
  local order, pos, pts = {}, where:totable(), at:totable()
  for i = 1, #pos do order[i] = i end
  table.sort(order, function(a, b) return pos[a] < pos[b] end)
  local spos, spts = {}, {}
  for i, k in ipairs(order) do spos[i], spts[i] = pos[k], pts[k] end
  ctx.corner_positions = spos
  ctx.params = common.ok("corner parameters", bs.params_through_corners(P, ctx.params,
    bs.vector.new(spos), bs.points.new(spts), ctx.settings.param, { closed = true }))
  return as_table(idx)
end

-- The smallest and largest counts the search may try.
local function count_range(P, ctx)
  local m, p = #P, ctx.settings.degree
  local nmin = math.max(p + 1, closed(ctx) and (#ctx.corners * p + 4) or 0, math.min(8, m // 2))
  -- small sections may use as many as the paper's 50% rule; large ones a third,
  -- at most 4000 (a noisy section stops far below, at its noise level)
  local nmax = ctx.settings.count_max or math.min(m <= 500 and m // 2 or m // 3, 4000)
  nmax = math.max(math.min(nmax, m), nmin)
  return math.min(nmin, nmax), nmax
end

-- Count search. Without tol: grow the count until the weighted RMS distance is at
-- the noise level (what a least-squares fit of the truth would leave:
-- sigma sqrt(1 - n/m)); past it, keep growing only while each step still cuts the
-- RMS by 30% (clean data, where the estimate is only the model's own bias; on
-- noisy data the RMS then barely moves). If the noise level is never reached, stop
-- when two steps in a row improve less than 2% on the best fit (knots move with the
-- count, so more is not always better) and keep the best. With tol: grow until the
-- maximum distance is at most tol.
local function size_of(P)
  local m, b, size = #P, { P:get(1) }, 0
  for i = 2, m, math.max(1, m // 64) do
    local q, dd = { P:get(i) }, 0
    for k = 1, #b do dd = dd + (q[k] - b[k]) ^ 2 end
    size = math.max(size, math.sqrt(dd))
  end
  return size
end

function steps.count(P, ctx)
  local m = #P
  local n, nmax = count_range(P, ctx)
  local tol, sigma = ctx.settings.tol, ctx.sigma
  local floor = 1e-7 * size_of(P) -- clean data: no need to go below a relative 1e-7
  local tries, best, chosen, stalls = {}, nil, nil, 0
  while true do
    local C, u, d, N, wm, mfit = fit_corrected(ctx, P, n, ctx.sub and 0 or 1, ctx.sub ~= nil)
    local rms, max = stats(d, wm, ctx.settings.robust and ctx.settings.huber * math.max(sigma, 1e-12))
    local fit = { curve = C, params = u, distances = d, count = N, rms = rms, max = max }
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
    end
    if n >= nmax or (not chosen and stalls >= 2) then break end
    n = math.min(nmax, math.max(n + 1, math.floor(n * 1.3 + 0.5)))
  end
  ctx.tries, ctx.search = tries, chosen or best
  return ctx.search.count
end

-- Final fit: the count found, `correct` rounds of parameter correction.
function steps.fit(P, ctx)
  -- on large sections one correction round does nearly all the good (and each costs a
  -- projection of every point)
  local rounds = ctx.settings.correct
  if ctx.sub then rounds = math.min(rounds, 1) end
  local C, u, d = fit_corrected(ctx, P, ctx.count, rounds)
  ctx.params_final, ctx.distances, ctx.distances_of = u, d, C
  return C
end

-- Optional Huber reweighting: points farther than huber x sigma from the curve get
-- weight w c/|d|; three rounds.
function steps.reweight(P, ctx)
  if not ctx.settings.robust then return ctx.curve end
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

function steps.measure(P, ctx)
  local d = ctx.distances -- the fit's last projection, when it is of this very curve
  if ctx.distances_of ~= ctx.curve or d == nil then
    d = select(2, ctx.curve:project(P, ctx.params_final or ctx.params, NEWTON))
  end
  local max, imax = d:max()
  return { residuals = d:totable(), rms = d:rms(), max = max or 0, max_index = imax or 1 }
end

-- }======================================================================

function M.run(P, opts) return common.run(M, P, opts) end

-- The report: the common fields plus what this strategy chose.
function M.report(ctx)
  local rep = common.report(ctx)
  rep.sigma = ctx.sigma
  rep.corners = ctx.corners
  rep.tries = ctx.tries
  return rep
end

return M
