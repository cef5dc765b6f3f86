-- lua/bsfit/strategy/periodic.lua
-- Our improvement on the paper (docs/method.md §13): the same weights and control-point
-- count, but a true periodic weighted least-squares fit, so the curve is C^{p-1}
-- at the seam by construction and needs no start-point search or tangent
-- correction. With `tol`, the count is instead the smallest one whose maximum
-- deviation is at most tol.
--
--   local periodic = require "bsfit.strategy.periodic"
--   local C, rep = periodic.run(P, {tol = 1e-3})
--
-- opts: any step name replaces that step (function f(P, ctx) -> value, or a plain
-- value); settings: degree (3), param ("chord"), tol (none), point_weights,
-- trust (0.1), knot_rule ("periodic-averaging"; "carvalho-closed" for the paper's
-- closed knots), solver ("auto": Cholesky, QR when the normal matrix is
-- ill-conditioned; see bs.fitter), closed (true; false fits an open curve with the
-- same weights and count: open chord parameters, clamped averaging knots, open
-- weighted least squares).
--
-- Down-weighted points (point_weights below trust x their median, the rule of
-- bs.params_trusted) are the file saying "do not follow these": they must not steer
-- the fit through anything but their own small weight. So with point_weights the
-- parameters are chord lengths over the trusted points (an outlier would stretch its
-- neighbours' chords), the circumradius weights are read off the trusted points (an
-- outlier looks like a tight corner, and makes its neighbours look like one), and the
-- seam search and `tol` judge a fit by the trusted points (the deviation at an
-- outlier is the one the fit is told to keep).
--
-- rep: as bsfit.strategy.carvalho's (start_index: the point the parameters and
-- knots start at, chosen by the seam search; candidates: the seams tried), plus
-- tries (the counts tried by the tolerance search, with their fit's max deviation)
-- and, with untrusted points, max_trusted, rms_trusted, max_trusted_index.

local bs = require "bsfit"
local common = require "bsfit.strategy.common"

local M = { name = "periodic" }

M.settings = { degree = 3, param = "chord", closed = true, trust = 0.1, solver = "auto" }
M.optional = { point_weights = true, tol = true, knot_rule = true }

M.order = { "params", "weights", "count", "knots", "fit", "start", "refine", "measure" }

local steps = {}
M.steps = steps

-- Chord parameters (docs/method.md §2; closed: in [0, 1), the closing chord counted), over
-- the trusted points when some are down-weighted.
steps.params = common.params_trusted(nil)

-- Circumradius weights (docs/method.md §7) of the shape the trusted points describe, times
-- the point_weights.
steps.weights = common.weights_circumradius_trusted

steps.count = common.count_inversions

-- The averaging knot rules (docs/method.md §3-4) and whether each closes the curve.
local RULES = { ["periodic-averaging"] = true, ["carvalho-closed"] = true,
                ["periodic-uniform"] = true, averaging = false, uniform = false }

-- Averaging knots (docs/method.md §3-4) by the rule of setting knot_rule: closed curves
-- default to "periodic-averaging" (the α-interpolation taken consistently around
-- the circle; "carvalho-closed" is the paper's literal rule), open ones to
-- "averaging". The step gives the rule's name, and the fitter places those knots on
-- the parameters of each fit (bs.knots.averaging would give the same knots, at the
-- price of a Knots object and a reconfiguration per fit of the searches). An
-- override may give the knots themselves: a bsfit.Knots, or one period (closed) /
-- the full vector (open) as a Vector or table.
function steps.knots(_, ctx)
  local closed = common.closed(ctx)
  local rule = ctx.settings.knot_rule or (closed and "periodic-averaging" or "averaging")
  if RULES[rule] ~= closed then
    error(("periodic: knot_rule '%s' is not a rule for %s curves"):format(tostring(rule),
          closed and "closed" or "open"), 0)
  end
  return rule
end

-- The periodic weighted least-squares fit; ctx.fit_report keeps the fitter's
-- report (deviations at the parameters, used by the seam and tolerance searches).
-- One fitter serves every fit of the run; it is reconfigured only when the knots
-- (or the rule and count that place them) change.
function steps.fit(P, ctx)
  local cache, K, closed = ctx.cache, ctx.knots, common.closed(ctx)
  local p, n, F = ctx.settings.degree, ctx.count, ctx.cache.fitter
  if type(K) == "string" then
    local o = cache.fitter_rule
    if F == nil or o == nil or o.rule ~= K or o.count ~= n or o.degree ~= p or o.periodic ~= closed then
      o = { degree = p, count = n, rule = K, periodic = closed, solver = ctx.settings.solver }
      if F then F:configure(o) else F = bs.fitter(o) end
      cache.fitter_rule = o
    end
  else
    local o = { degree = p, knots = K, periodic = closed, solver = ctx.settings.solver }
    if F then F:configure(o) else F = bs.fitter(o) end
    cache.fitter_rule = nil
  end
  cache.fitter = F
  local C, rep = common.ok("periodic fit", F:fit(P, ctx.params, ctx.weights))
  ctx.fit_report = rep
  return C
end

-- {======================================================================
-- Seam search and tolerance search
-- =======================================================================

-- Where the refits of the searches time their steps: not in the run's times, where
-- the searching step's own time already counts them.
local function subtimes(ctx)
  local t = ctx.cache.subtimes
  if t == nil then t = {}; ctx.cache.subtimes = t end
  return t
end

-- The run's data rotated so that point k is first: a sub-context with the rotated
-- points, weights and point_weights, and their parameters: the params step rerun
-- on them (an override function sees the rotated point_weights in ctx.settings),
-- or, when `params` was given as a value, that value rotated. k = 1: ctx itself.
local function rotation(ctx, k)
  if k == 1 then return ctx end
  local sub = setmetatable({ times = subtimes(ctx), P = ctx.P:rotate(k),
                             weights = common.rotate_vector(ctx.weights, k) }, { __index = ctx })
  local pw = ctx.settings.point_weights
  sub.settings = setmetatable({ point_weights = pw and common.rotate_vector(pw, k) },
                              { __index = ctx.settings })
  local o = ctx.opts.params
  if o == nil or type(o) == "function" or (getmetatable(o) or {}).__call then
    sub.params = common.call(sub, "params", sub.P)
  else
    sub.params = common.rotate_params(ctx.params, k)
  end
  return sub
end

-- Refit the data of rotation r with knot rule `rule` and n control points (the
-- knots and fit steps rerun, overrides included). Returns the sub-context: its
-- fit and fit_report.
local function refit(r, rule, n)
  local sub = setmetatable({ times = subtimes(r), count = n or r.count }, { __index = r })
  sub.settings = setmetatable({ knot_rule = rule }, { __index = r.settings })
  sub.knots = common.call(sub, "knots", sub.P)
  sub.fit = common.call(sub, "fit", sub.P)
  return sub
end

-- What the searches minimise: a fit's maximum deviation at the parameters over the
-- trusted points (every point when all are trusted). rep: the fit's report, on the
-- points rotated so that k is first.
local function score(ctx, rep, k)
  local t = common.trusted(ctx)
  if t == nil then return rep.max end
  return common.trusted_max(rep.residuals, t, k)
end

-- The sharpest point: the smallest angle (docs/method.md §8's angle), over the trusted
-- points' polygon when some are down-weighted (an outlier makes a spike).
local function sharpest(P, ctx)
  local t = common.trusted(ctx)
  if t == nil or t.points == nil then
    local _, i = bs.geom.angles(P, { closed = true }):min()
    return i
  end
  local _, j = bs.geom.angles(t.points, { closed = true }):min()
  return common.trusted_index(t, j)
end

-- Seam and knot search (closed curves): a periodic fit has no seam, but its
-- averaging knots start at the first point, so where the points start and which
-- closed rule places the knots change the fit. Tries the first point and the
-- sharpest one (smallest angle, where a knot helps most) with both closed rules,
-- and keeps the smallest maximum deviation at the parameters (over the trusted
-- points). A try is skipped when it is provably the fit already made: the
-- "periodic-averaging" knots of N control points on m points sit at the fractional
-- point indices j m/N, so starting at point k moves them to k - 1 + j m/N, the same
-- set when (k - 1) N is a multiple of m; the parameters only shift by a constant,
-- which moves no curve (default params and knots steps). A plain value of `start`
-- (an index) fixes the seam and keeps the knot rule.
function steps.start(P, ctx)
  local rule0 = ctx.settings.knot_rule
  local best = { r = ctx, k = 1, rule = rule0, max = score(ctx, ctx.fit_report, 1), curve = ctx.fit }
  ctx.seam, ctx.start_index = best, 1
  if not common.closed(ctx) then return 1 end
  rule0 = rule0 or "periodic-averaging"
  local m, n = #P, ctx.count
  local sharp = sharpest(P, ctx)
  ctx.candidates = { 1 }
  if sharp ~= 1 then ctx.candidates[2] = sharp end
  local shift_free = ctx.opts.params == nil and ctx.opts.knots == nil
  for _, k in ipairs(ctx.candidates) do
    local r
    for _, rule in ipairs { "periodic-averaging", "carvalho-closed" } do
      local same = (k == 1 and rule == rule0)
        or (shift_free and rule == "periodic-averaging" and (k - 1) * n % m == 0)
      if not same then
        if r == nil then
          local fine, rr = pcall(rotation, ctx, k)
          r = fine and rr or false
        end
        local ok, sub = false, nil
        if r then ok, sub = pcall(refit, r, rule) end
        if ok then
          local e = score(ctx, sub.fit_report, k)
          if e < best.max then best = { r = r, k = k, rule = rule, max = e, curve = sub.fit } end
        end
      end
    end
  end
  ctx.seam = best
  ctx.curve, ctx.start_index = best.curve, best.k
  return best.k
end

-- Fit with n control points at the chosen seam and rule; returns the curve and
-- its score.
local function fit_count(ctx, n)
  local seam = ctx.seam
  local sub = refit(seam.r, seam.rule, n)
  return sub.fit, score(ctx, sub.fit_report, seam.k)
end

-- Tolerance search (docs/method.md §13): the fit's deviation at the parameters bounds the
-- closest-point deviation from above, so meeting tol with it meets tol (over the
-- trusted points, with point_weights: rep.max_trusted). Doubles the count until
-- tol is met (n = m interpolates), then bisects. Without tol, keeps the fit.
function steps.refine(P, ctx)
  local k = ctx.start
  if math.type(k) ~= "integer" or k < 1 or k > #P then
    error(("periodic: step 'start' must give a point index 1..%d, got %s"):format(#P, tostring(k)), 0)
  end
  if ctx.start_index ~= k then -- fixed by an override: fit with the seam there
    local r = rotation(ctx, k)
    local sub = k == 1 and ctx or refit(r, ctx.settings.knot_rule)
    ctx.seam = { r = r, k = k, rule = ctx.settings.knot_rule, max = score(ctx, sub.fit_report, k) }
    ctx.curve, ctx.start_index = sub.fit, k
  end
  local tol = ctx.settings.tol
  if tol == nil then return ctx.curve end
  if type(tol) ~= "number" or not (tol >= 0) then
    error("bad argument #2 to 'run' (option 'tol' must be a number >= 0)", 0)
  end
  local m, tries = #P, {}
  local lo, hi, best = ctx.count, ctx.count, ctx.curve
  local max = ctx.seam.max
  tries[1] = { count = lo, max = max }
  while max > tol and hi < m do
    lo, hi = hi, math.min(2 * hi, m)
    best, max = fit_count(ctx, hi)
    tries[#tries + 1] = { count = hi, max = max }
  end
  while hi - lo > 1 and max <= tol do
    local mid = (lo + hi) // 2
    local C, e = fit_count(ctx, mid)
    tries[#tries + 1] = { count = mid, max = e }
    if e <= tol then hi, best = mid, C else lo = mid end
  end
  ctx.count, ctx.tries = hi, tries
  return best
end

-- }======================================================================

steps.measure = common.measure

function M.run(P, opts)
  local C, rep = common.run(M, common.drop_closing_point(P, opts))
  return C, rep
end

return M
