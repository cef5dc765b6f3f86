-- lua/bsfit/strategy/carvalho.lua
-- The Pereira & Carvalho method (docs/method.md), faithfully: chord parameters,
-- circumradius weights, the 50% control-point count rule, an open weighted
-- least-squares fit on averaging knots, the paper's closing by wrapping (P-12,
-- P-13 as docs/method.md §3-4 reads them), the start-point search over the aligned points
-- (refitting each candidate) and the tangent correction of P_1, P_2.
--
--   local carvalho = require "bsfit.strategy.carvalho"
--   local C, rep = carvalho.run(P, opts)
--
-- opts: any step name below replaces that step (a function f(P, ctx) -> value,
-- or a plain value taken as the step's result, e.g. {count = 24}); settings:
-- degree (3), param ("chord"), point_weights (per-point weights multiplied into
-- the weighting rule's), closed (true; false raises), solver ("cholesky", the
-- paper's normal equations; "qr" or "auto": see bs.fitter), candidates (16: at most
-- that many start-point candidates are refitted, those of largest angle; "all" for
-- the paper's literal search, one refit per qualifying point). Unknown names raise.
-- rep: points, count, inflections, weights (Vector), start_index (1-based index
-- of the input point the curve starts at), candidates (indices tried), candidate_dt
-- (dt_1 + dt_2 of each), candidates_tried (#candidates), candidates_found (how many
-- points qualified), rms, max, max_index, residuals (closest-point distances
-- of the input points, input order), times (ms per step), total_ms.

local bs = require "bsfit"
local common = require "bsfit.strategy.common"

local M = { name = "carvalho" }

-- The report: the common fields, and how many start-point candidates qualified.
function M.report(ctx)
  local rep = common.report(ctx)
  rep.candidates_found = ctx.candidates_found
  return rep
end

M.settings = { degree = 3, param = "chord", closed = true, solver = "cholesky", candidates = 16 }
M.optional = { point_weights = true }

M.order = { "params", "weights", "count", "knots", "fit", "close", "start", "tangent", "measure" }

local steps = {}
M.steps = steps

-- {======================================================================
-- The open fit and the closing (docs/method.md §2-6)
-- =======================================================================

-- Open chord parameters, ū_0 = 0 .. ū_j = 1 (P-8, P-9).
steps.params = common.params_chord(false)

steps.weights = common.weights_circumradius

steps.count = common.count_inversions

-- Averaging knots for the open fit (P-10, P-11).
function steps.knots(_, ctx)
  return common.ok("knots", bs.knots.averaging { params = ctx.params, count = ctx.count,
                                               degree = ctx.settings.degree, closed = false })
end

-- A fitter kept in the strategy's context and reused for every refit of the
-- start-point search (same size, new knots: no new workspace).
local function fitter(ctx, K)
  local F = ctx.cache.fitter
  local o = { degree = ctx.settings.degree, knots = K, solver = ctx.settings.solver }
  if F then return F:configure(o) end
  F = bs.fitter(o)
  ctx.cache.fitter = F
  return F
end

-- Open weighted least squares (P-3 .. P-7).
function steps.fit(P, ctx)
  local C = common.ok("open fit", fitter(ctx, ctx.knots):fit(P, ctx.params, ctx.weights))
  return C
end

-- The paper's closing (docs/method.md §6): the open fit's N control points read as a
-- periodic polygon with the "carvalho-closed" knots of the closed parameters.
function steps.close(P, ctx)
  local open, p = ctx.fit, ctx.settings.degree
  local ctrl = open:control_points()
  local u = bs.params(P, ctx.settings.param, { closed = true })
  local K = common.ok("closing knots", bs.knots.averaging {
    params = u, count = #ctrl, degree = p, closed = true, rule = "carvalho-closed" })
  return bs.curve.new { degree = p, knots = K, control_points = ctrl, periodic = true }
end

-- }======================================================================

-- {======================================================================
-- Start point (docs/method.md §8) and tangent correction (docs/method.md §9-10)
-- =======================================================================

-- The setting `candidates`: a count >= 1, or "all" (math.huge).
local function candidate_limit(v)
  if v == "all" then return math.huge end
  if math.type(v) ~= "integer" or v < 1 then
    error("bad argument #2 to 'run' (option 'candidates' must be an integer >= 1 or \"all\")", 0)
  end
  return v
end

-- Candidates: the points whose angle exceeds mean + std/2 (population std);
-- when none does (all angles equal), the first point of largest angle. Each is a
-- refit of the whole section, so at most `limit` of them (the largest angles, ties
-- by index) are kept: the paper's literal search (limit = math.huge) costs m refits
-- on a section of m points. Returns the kept indices, increasing, and how many
-- points qualified.
function M.candidates(P, limit)
  local a = bs.geom.angles(P, { closed = true }):totable()
  local mean, std = common.mean_std(a)
  local c, best = {}, 1
  for i = 1, #a do
    if a[i] > mean + std / 2 then c[#c + 1] = i end
    if a[i] > a[best] then best = i end
  end
  if #c == 0 then c[1] = best end
  local found = #c
  if limit and #c > limit then
    table.sort(c, function(i, j) return a[i] > a[j] or (a[i] == a[j] and i < j) end)
    for k = #c, limit + 1, -1 do c[k] = nil end
    table.sort(c)
  end
  return c, found
end

-- dt_1 + dt_2: distances of control points P_1, P_2 of the closed curve C from
-- the tangent line through Q_0 with direction Q_1 - Q_0 (P-16).
function M.tangent_distance(C, Q)
  local o, q1 = common.point(Q, 1), common.point(Q, 2)
  local d = {}
  for k = 1, #o do d[k] = q1[k] - o[k] end
  local d1 = common.line_foot({ C:control_point(2) }, o, d)
  local d2 = common.line_foot({ C:control_point(3) }, o, d)
  return d1 + d2
end

-- The closed curve for the points rotated so that index k is first: the
-- params, knots, fit and close steps (user overrides included) rerun on them.
function M.refit(ctx, k)
  local Q = ctx.P:rotate(k)
  local sub = setmetatable({ P = Q, times = {}, weights = common.rotate_vector(ctx.weights, k) },
                           { __index = ctx })
  for _, name in ipairs { "params", "knots", "fit", "close" } do
    sub[name] = common.call(sub, name, Q)
  end
  return sub.close, Q
end

-- Start-point search: refit from every candidate, keep the smallest dt_1 + dt_2.
-- Returns the chosen 1-based index; ctx.curve becomes that candidate's curve and
-- ctx.start_points the rotated points.
function steps.start(P, ctx)
  local cand, found = M.candidates(P, candidate_limit(ctx.settings.candidates))
  local dts = {}
  ctx.candidates_found = found
  local best, bestdt, bestC, bestQ
  for i, k in ipairs(cand) do
    local C, Q
    if k == 1 then C, Q = ctx.close, P else C, Q = M.refit(ctx, k) end
    dts[i] = M.tangent_distance(C, Q)
    if bestdt == nil or dts[i] < bestdt then best, bestdt, bestC, bestQ = k, dts[i], C, Q end
  end
  ctx.candidates, ctx.candidate_dt = cand, dts
  ctx.curve, ctx.start_points, ctx.start_index = bestC, bestQ, best
  return best
end

-- Tangent correction: P_1 and P_2 replaced by their orthogonal projections onto
-- the tangent line through the start point. Works on a copy of ctx.curve. When an
-- override of `start` named the index (the search did not run), refits from it.
function steps.tangent(_, ctx)
  local k = ctx.start
  if math.type(k) ~= "integer" or k < 1 or k > #ctx.P then
    error(("carvalho: step 'start' must give a point index 1..%d, got %s"):format(#ctx.P, tostring(k)), 0)
  end
  if ctx.start_index ~= k then
    ctx.curve, ctx.start_points = M.refit(ctx, k)
    ctx.start_index = k
  end
  local Q = ctx.start_points or ctx.P
  local o, q1 = common.point(Q, 1), common.point(Q, 2)
  local d = {}
  for k = 1, #o do d[k] = q1[k] - o[k] end
  local C = ctx.curve:copy()
  for i = 2, 3 do
    local _, foot = common.line_foot({ C:control_point(i) }, o, d)
    C:set_control_point(i, table.unpack(foot))
  end
  ctx.tangent_line = { origin = o, direction = d }
  return C
end

steps.measure = common.measure

-- }======================================================================

function M.run(P, opts)
  if type(opts) == "table" and opts.closed == false then
    error("bad argument #2 to 'run' (carvalho fits closed sections only: use bsfit.strategy.periodic with closed = false)", 2)
  end
  local notes, map
  P, opts, notes = common.drop_closing_point(P, opts)
  local Q
  Q, opts, map = common.merge_repeats(P, opts, notes)
  local C, rep = common.run(M, Q, opts, notes)
  if map then common.unmerge_report(rep, map, #P) end
  rep.candidates_tried = #(rep.candidates or {})
  rep.candidates_found = rep.candidates_found or rep.candidates_tried
  return C, rep
end

return M
