-- lua/bsfit/strategy/periodic.lua
-- Our improvement on the paper (SPEC 2.8): the same weights and control-point
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
-- knot_rule ("periodic-averaging"; "carvalho-closed" for the paper's closed knots),
-- closed (true; false fits an open curve with the same weights and count: open
-- chord parameters, clamped averaging knots, open weighted least squares).
-- rep: as bsfit.strategy.carvalho's (start_index: the point the parameters and
-- knots start at, chosen by the seam search; candidates: the seams tried), plus
-- tries (the counts tried by the tolerance search, with their fit's max deviation).

local bs = require "bsfit"
local common = require "bsfit.strategy.common"

local M = { name = "periodic" }

M.settings = { degree = 3, param = "chord", closed = true }
M.optional = { point_weights = true, tol = true, knot_rule = true }

M.order = { "params", "weights", "count", "knots", "fit", "start", "refine", "measure" }

local steps = {}
M.steps = steps

-- Closed chord parameters in [0, 1), the closing chord counted (SPEC 2.1).
steps.params = common.params_chord(nil)

steps.weights = common.weights_circumradius

steps.count = common.count_inversions

-- Averaging knots (SPEC 2.2) by the rule of setting knot_rule: closed curves
-- default to "periodic-averaging" (the α-interpolation taken consistently around
-- the circle; "carvalho-closed" is the paper's literal rule), open ones to
-- "averaging".
function steps.knots(_, ctx)
  local closed = common.closed(ctx)
  local rule = ctx.settings.knot_rule or (closed and "periodic-averaging" or "averaging")
  return common.ok("knots", bs.knots.averaging { params = ctx.params, count = ctx.count, rule = rule,
                                               degree = ctx.settings.degree, closed = closed })
end

-- The periodic weighted least-squares fit; ctx.fit_report keeps the fitter's
-- report (max deviation at the parameters, used by the tolerance search).
function steps.fit(P, ctx)
  local o = { degree = ctx.settings.degree, knots = ctx.knots, periodic = common.closed(ctx) }
  local F = ctx.cache.fitter -- reused by the seam and tolerance searches
  if F then F:configure(o) else F = bs.fitter(o); ctx.cache.fitter = F end
  local C, rep = common.ok("periodic fit", F:fit(P, ctx.params, ctx.weights))
  ctx.fit_report = rep
  return C
end

-- Refit on the points rotated so that index k is first, with knot rule `rule`
-- and n control points (params, knots and fit steps rerun, overrides included).
-- Returns the sub-context: its fit, fit_report, P, weights and params.
local function refit(ctx, k, rule, n)
  local sub = setmetatable({ times = {}, count = n or ctx.count }, { __index = ctx })
  sub.settings = setmetatable({ knot_rule = rule }, { __index = ctx.settings })
  if k ~= 1 then
    sub.P = ctx.P:rotate(k)
    sub.weights = common.rotate_vector(ctx.weights, k)
    sub.params = common.call(sub, "params", sub.P)
  end
  for _, name in ipairs { "knots", "fit" } do sub[name] = common.call(sub, name, sub.P) end
  return sub
end

-- Seam and knot search (closed curves): a periodic fit has no seam, but its
-- averaging knots start at the first point, so where the points start and which
-- closed rule places the knots change the fit. Tries the first point and the
-- sharpest one (smallest angle, where a knot helps most) with both closed rules,
-- and keeps the smallest maximum deviation at the parameters. A plain value of
-- `start` (an index) fixes the seam and keeps the knot rule.
function steps.start(P, ctx)
  if not common.closed(ctx) then return 1 end
  local ang = bs.geom.angles(P, { closed = true }):totable()
  local sharp = 1
  for i = 2, #ang do if ang[i] < ang[sharp] then sharp = i end end
  local best = { sub = ctx, k = 1, rule = ctx.settings.knot_rule or "periodic-averaging" }
  best.max = ctx.fit_report.max
  ctx.candidates = { 1 }
  if sharp ~= 1 then ctx.candidates[2] = sharp end
  for _, k in ipairs(ctx.candidates) do
    for _, rule in ipairs { "periodic-averaging", "carvalho-closed" } do
      if not (k == 1 and rule == best.rule) then
        local ok, sub = pcall(refit, ctx, k, rule)
        if ok and sub.fit_report.max < best.max then
          best = { sub = sub, k = k, rule = rule, max = sub.fit_report.max }
        end
      end
    end
  end
  ctx.seam = best
  ctx.curve, ctx.start_index = best.sub.fit, best.k
  return best.k
end

-- Fit with n control points at the chosen seam and rule; returns the curve and
-- the fit's max deviation at the parameters.
local function fit_count(ctx, n)
  local seam = ctx.seam or { k = 1, rule = ctx.settings.knot_rule }
  local sub = refit(ctx, seam.k, seam.rule, n)
  return sub.fit, sub.fit_report.max
end

-- Tolerance search (SPEC 2.8): the fit's deviation at the parameters bounds the
-- closest-point deviation from above, so meeting tol with it meets tol. Doubles
-- the count until tol is met (n = m interpolates), then bisects. Without tol,
-- keeps the fit.
function steps.refine(P, ctx)
  local k = ctx.start
  if math.type(k) ~= "integer" or k < 1 or k > #P then
    error(("periodic: step 'start' must give a point index 1..%d, got %s"):format(#P, tostring(k)), 0)
  end
  if ctx.start_index ~= k then -- fixed by an override: fit with the seam there
    local sub = refit(ctx, k, ctx.settings.knot_rule)
    ctx.seam = { k = k, rule = ctx.settings.knot_rule, max = sub.fit_report.max }
    ctx.curve, ctx.start_index = sub.fit, k
  end
  local tol = ctx.settings.tol
  if tol == nil then return ctx.curve end
  if type(tol) ~= "number" or not (tol >= 0) then
    error("bad argument #2 to 'run' (option 'tol' must be a number >= 0)", 0)
  end
  local m, tries = #P, {}
  local lo, hi, best = ctx.count, ctx.count, ctx.curve
  local max = ctx.seam and ctx.seam.max or ctx.fit_report.max
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

steps.measure = common.measure

function M.run(P, opts)
  local C, rep = common.run(M, P, opts)
  return C, rep
end

return M
