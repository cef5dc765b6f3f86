-- lua/bsfit/strategy/auto.lua
-- The default strategy (beyond the paper): reads the noise level off the data,
-- grows the control-point count until the curve follows the shape but not the
-- noise, keeps sharp corners sharp, corrects the parameters to foot points, and
-- never lets a down-weighted point distort its neighbours.
--
--   local auto = require "bsfit.strategy.auto"
--   local C, rep = auto.run(P, {point_weights = w})
--
-- Steps, in order (each replaceable by name, like every strategy: a function f(P, ctx)
-- or a plain value, e.g. {count = 24} or {corners = {}}); docs/auto.md has the method:
--   ends     open or closed from the data when the setting closed = "auto" (default;
--            bsfit.strategy.closure)
--   sigma    noise level normal to the curve, from the data alone (bs.geom.noise_sigma)
--   segment  lines, circular arcs and free runs (bs.geom.segment) when they explain the
--            section: exactly, or within the noise they show (bsfit.strategy.pieces_path);
--            {} otherwise. When it finds them, `assemble` makes the curve and the
--            smooth-path steps below (params .. fit: bsfit.strategy.smooth_path) stand aside
--   (ends, sigma and segment read the trusted points only: weight >= trust x median)
--   params   chord parameters over the trusted points (weight >= trust x median), on
--            anchors where samples crowd closer than the noise (bsfit.strategy.anchors)
--   weights  the file's weights (point_weights), else 1
--   corners  sharp corners (bs.geom.corners): triple knots, the spans beside them kept
--            long enough to read the sides' directions through the noise
--   count    the search: counts grow geometrically until the weighted RMS distance of
--            the trusted points reaches the noise level (or a step buys no more than fitting noise would);
--            `tol` asks for a maximum distance instead
--   fit      the final fit: `correct` rounds of parameter correction (foot points)
--   assemble the one curve of the pieces: exact lines and arcs, fitted free runs, G1 where
--            they touch, C0 at corners (bsfit.strategy.sharp; false when there are no
--            pieces, unless the smooth curve missed its samples: pieces_path)
--   reweight optional Huber reweighting, run when the setting robust = true (a step
--            and a setting cannot share a name: opts[step] replaces the step)
--   loops    self-intersection check of closed curves; refit with other counts, or the
--            pieces, or no corners; else a warning (bsfit.strategy.loops)
--   measure  distances of the points to the curve (vectorised projection in C)
-- Settings: degree (3), param ("chord"), closed ("auto"; true, false), trust (0.1),
-- correct (3), robust (false), huber (1.345), solver ("auto": Cholesky, QR when the
-- normal matrix is ill-conditioned; see bs.fitter), count_max (m/2 up to 500 points,
-- then m/3, at most 4000); optional: point_weights, tol.
-- rep: count, sigma, corners (1-based indices), tries ({count, rms, max} per fit of the
-- search), rms, max, max_index, residuals (distances), times per step, closed,
-- closed_ambiguous, crossings, pieces (when segmented) and pieces_sigma (the noise level they
-- were found at, 0 on exact data), pieces_rejected (why a noisy section kept the smooth
-- path), warnings.

local bs = require "bsfit"
local common = require "bsfit.strategy.common"
local sharp = require "bsfit.strategy.sharp"
local closure = require "bsfit.strategy.closure"
local pieces = require "bsfit.strategy.pieces_path"
local smooth = require "bsfit.strategy.smooth_path"
local loops = require "bsfit.strategy.loops"

local M = { name = "auto" }

M.settings = { degree = 3, param = "chord", closed = "auto", trust = 0.1, correct = 3,
               robust = false, huber = 1.345, solver = "auto" }
M.optional = { point_weights = true, tol = true, count_max = true }

M.order = { "ends", "sigma", "segment", "params", "weights", "corners", "count", "fit",
            "assemble", "reweight", "loops", "measure" }

local steps = {}
M.steps = steps

-- {======================================================================
-- Steps: each delegates to the module of its concept
-- =======================================================================

function steps.ends(P, ctx) return closure.decide(P, ctx) end

function steps.sigma(P, ctx)
  if #P < 6 then return 0 end
  -- the noise of the trusted points (a gross outlier of weight 1e-3 is not noise), of a
  -- large closed section on its subsample from where the segmentation reads it (read from
  -- the data's first point, a rounded rectangle of 10^5 samples at noise 1e-4 went through
  -- its pieces from two starts of three)
  local t, closed = common.trusted(ctx), common.closed(ctx)
  local Q = t and t.points and t.n >= 6 and t.points or P
  Q = common.thinned_closed(Q, closed) or Q
  local sigma, msg, code = bs.geom.noise_sigma(Q, { closed = closed })
  if not sigma and code == "EDEGENERATE" then
    -- too few distinct points to estimate from (6 samples of a circle, repeats): they are
    -- followed as exact data, and the report says so
    common.warn(ctx, "too few distinct points to estimate the noise: the points are taken as exact")
    return 0
  end
  return common.ok("noise estimate", sigma, msg, code)
end

function steps.segment(P, ctx) return pieces.segment(P, ctx) end

-- the smooth path's steps stand aside when the pieces make the curve
function steps.params(P, ctx)
  if not pieces.taken(ctx) then return smooth.params(P, ctx) end
  return bs.params(P, ctx.settings.param, { closed = common.closed(ctx) })
end

function steps.weights(P, ctx)
  local pw = ctx.settings.point_weights
  if pw == nil then return bs.weights.uniform(P) end
  if type(pw) == "table" then pw = bs.vector.new(pw) end
  if #pw ~= #P then
    error(("auto: point_weights has %d values for %d points"):format(#pw, #P), 0)
  end
  return pw
end

function steps.corners(P, ctx)
  if pieces.taken(ctx) then return sharp.corner_samples(P, ctx.segment) end
  return smooth.corners(P, ctx)
end

function steps.count(P, ctx)
  if pieces.taken(ctx) then return 0 end -- the assemble step's
  return smooth.count(P, ctx)
end

function steps.fit(P, ctx)
  if pieces.taken(ctx) then return false end -- the assemble step's
  return smooth.fit(P, ctx)
end

function steps.assemble(P, ctx) return pieces.assemble(P, ctx) end

function steps.reweight(P, ctx)
  if not ctx.settings.robust or pieces.taken(ctx) then return ctx.curve end
  return smooth.reweight(P, ctx)
end

function steps.loops(P, ctx) return loops.check(P, ctx) end

function steps.measure(P, ctx)
  if pieces.taken(ctx) then
    return common.measure_of(ctx, sharp.distances(ctx.curve, P, ctx.segment))
  end
  local d = ctx.distances -- the fit's last projection, when it is of this very curve
  if ctx.distances_of ~= ctx.curve or d == nil then
    d = select(2, ctx.curve:project(P, ctx.params_final or ctx.params, smooth.NEWTON))
  end
  return common.measure_of(ctx, d)
end

-- }======================================================================

function M.run(P, opts) return common.run(M, common.drop_closing_point(P, opts)) end

-- The report: the common fields plus what this strategy chose.
function M.report(ctx)
  local rep = common.report(ctx)
  rep.sigma = ctx.sigma
  rep.corners = ctx.corners
  rep.tries = ctx.tries
  rep.closed = common.closed(ctx)
  rep.closed_ambiguous = ctx.closed_ambiguous or false
  rep.crossings = ctx.loops or 0
  if pieces.taken(ctx) then
    local t = common.trusted(ctx)
    rep.pieces = sharp.as_drawn(ctx.P, ctx.segment, t and t.isout, rep.residuals)
    rep.pieces_sigma = ctx.segment_sigma
  end
  rep.pieces_rejected = ctx.sharp_rejected
  -- warnings: appended to those the common report may already carry
  if ctx.warnings and #ctx.warnings > 0 then
    rep.warnings = rep.warnings or {}
    for _, w in ipairs(ctx.warnings) do rep.warnings[#rep.warnings + 1] = w end
  end
  return rep
end

return M
