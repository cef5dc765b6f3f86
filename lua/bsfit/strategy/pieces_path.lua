-- lua/bsfit/strategy/pieces_path.lua
-- The pieces path of the auto strategy (docs/auto.md, "When the pieces are used"): which
-- lines, arcs and free runs a section takes (exact data, noisy data through the tests of
-- bsfit.strategy.noisy_pieces, the trusted points alone), the swap to them where the smooth
-- curve misses its own samples, and their one curve (bsfit.strategy.sharp).
--
--   local pieces = require "bsfit.strategy.pieces_path"
--   pieces.segment(P, ctx)   -- the segment step: the pieces, or {}
--   pieces.taken(ctx)        -- is the section made of its pieces?
--   pieces.assemble(P, ctx)  -- the assemble step: their curve, or false

local bs = require "bsfit"
local common = require "bsfit.strategy.common"
local sharp = require "bsfit.strategy.sharp"
local noisy = require "bsfit.strategy.noisy_pieces"
local closure = require "bsfit.strategy.closure"

local M = {}

-- May the pieces make the curve? Not when a step they would bypass was replaced or a count
-- or tolerance was asked for.
function M.allowed(ctx)
  local o = ctx.opts
  return o.count == nil and o.corners == nil and o.fit == nil and ctx.settings.tol == nil
end

-- Is the section made into one curve of lines, arcs and free runs (the segment step
-- found features), rather than fitted as one smooth curve?
function M.taken(ctx)
  return type(ctx.segment) == "table" and #ctx.segment > 0 and M.allowed(ctx)
end


-- The pieces of exact data (bs.geom.segment at sigma = 0), or nil. A large section is
-- screened on its subsample `sub` first: noisy data has no exact runs. `pieces`: the
-- segmentation already made (by the ends step), if any.
local function exact_pieces(P, ctx, sub, pieces)
  if not pieces and sub then
    local screen = common.ok("segmentation", bs.geom.segment(sub, { closed = common.closed(ctx) }))
    if not sharp.has_features(screen, #sub) then return nil end
  end
  pieces = pieces or common.ok("segmentation", bs.geom.segment(P, { closed = common.closed(ctx) }))
  return sharp.has_features(pieces, #P) and pieces or nil
end

-- The pieces of the trusted points t.points alone (down-weighted points are no samples of
-- a line or an arc), given back on all of P (sharp.spread); the free runs are then fitted
-- to every point with its weight. {} when the trusted points make no pieces.
-- idx[j]: the index among all of the j-th trusted point of t, found when asked (spread asks
-- once per piece; a table of every index was a loop over all points in Lua)
local function trusted_indices(t)
  return setmetatable({}, { __index = function(_, j) return common.trusted_index(t, j) end })
end

local function trusted_pieces(P, ctx, t)
  if not t.points or t.n < 6 then return {} end
  local Q, idx = t.points, trusted_indices(t)
  local pieces = exact_pieces(Q, ctx, common.thinned(Q))
  if pieces then ctx.segment_sigma = 0
  else
    local why, found
    pieces, why, found = noisy.find(Q, ctx.sigma, common.closed(ctx))
    ctx.sharp_rejected, ctx.sharp_disagreed = why, found.disagreed
    if found.candidate then
      ctx.sharp_candidate = { sigma = found.candidate.sigma,
        pieces = sharp.spread(found.candidate.pieces, idx, #P, common.closed(ctx)) }
    end
    if pieces then ctx.segment_sigma = found.sigma end
  end
  return pieces and sharp.spread(pieces, idx, #P, common.closed(ctx)) or {}
end

-- Lines, arcs and free runs (bs.geom.segment), when lines and arcs explain the section:
--   exact data: runs of 3 samples collinear, or 4 concyclic, to 1e-10 of the size,
--     holding half the samples (this does not happen by chance under noise);
--   noisy data: when the tests of bsfit.strategy.noisy_pieces pass (the noise read off
--     the pieces agrees with the windows', the pieces hold the samples and meet, their
--     corners are confirmed, their one curve stays within the noise).
-- Returns the pieces, or {} (one smooth curve).
local function segment_pieces(P, ctx)
  -- Huber reweighting asks for a fit that discounts samples by their distance: the pieces
  -- follow every sample they hold, so such sections take the smooth path
  if P:dim() ~= 2 or ctx.settings.robust then return {} end
  if #P < 6 then -- too few to read a noise off: exact lines and arcs only (a circle of 4)
    local exact = exact_pieces(P, ctx, nil, ctx.cache.exact_pieces)
    if exact then ctx.segment_sigma = 0; return exact end
    return {}
  end
  local t = common.trusted(ctx)
  if t then return trusted_pieces(P, ctx, t) end
  local sub = common.subsample(ctx, P)
  local exact = exact_pieces(P, ctx, sub and sub.P, ctx.cache.exact_pieces)
  if exact then ctx.segment_sigma = 0; return exact end
  local pieces, why, found = noisy.find(P, ctx.sigma, common.closed(ctx))
  ctx.sharp_rejected, ctx.sharp_candidate = why, found.candidate -- for the loops step
  ctx.sharp_disagreed = found.disagreed -- for the assemble step (pieces_for_misfit)
  if pieces then ctx.segment_sigma, ctx.sharp_curve = found.sigma, found.curve end
  return pieces or {}
end

-- Lines, arcs and free runs, when they explain the section (segment_pieces), or {}.
function M.segment(P, ctx)
  local pieces = segment_pieces(P, ctx)
  -- a closure the ends step found clear by the spacing alone, which the pieces make only by
  -- running on far past both end samples (sharp.closure_unsampled): three sides of a
  -- quadrilateral, their gap like a step, closed as a triangle no sample saw
  if ctx.closing and common.closed(ctx) and not ctx.closed_ambiguous and #pieces > 1 and
     sharp.closure_unsampled(P, pieces) then
    closure.doubt(ctx, "; the pieces close it only past both end samples")
  end
  return pieces
end

-- The options of sharp.assemble: the free runs fitted to the trusted points with their
-- weights, at noise level sigma.
function M.assembly(ctx, sigma)
  local pw, t = ctx.settings.point_weights, common.trusted(ctx)
  return { closed = common.closed(ctx), sigma = sigma or 0, weights = pw and common.as_table(pw) or nil,
           skip = t and t.isout }
end

-- A smooth curve that misses its own samples by more than MISFIT times the noise, when the
-- noise read off lines and arcs disagreed with the windows' (or no level of theirs matched
-- it): the pieces at that noise (at the windows' when none matched), when they pass every
-- other test of bsfit.strategy.noisy_pieces (confirmed corners, within 6 sigma of every
-- sample, no crossing) and miss the samples by less than it does. Two estimates of
-- the noise from 20 samples disagree by 25% by chance: a D of 10 uneven samples per side
-- at noise 1e-4 of its size read 1.29 times the windows' noise off its line and arc, and
-- its smooth curve, without the corners between samples, bulged 0.22 from a sample
-- (100 sigma) and 1.15 from the true outline. Where the two agreed but a test of the
-- screen refused the pieces (a bridge, a weak corner of two lines of 3 samples), the
-- smooth curve is judged in the pieces' noise s instead (on a sparse section the windows
-- read the bends between samples as noise, 5 to 20 times too high) and the pieces at s are
-- tried leniently (noisy.at): a T of 3 uneven samples per side at noise 1e-3 missed a
-- sample by 28 s and its outline by 17 times the floor, its pieces 1.2. Returns the
-- pieces' curve, or nil.
local MISFIT = 6

-- The noise to try the pieces at, the unit to judge the smooth curve in, and whether to
-- try them leniently; nil when no swap is asked. The sharp_* fields are set by the segment
-- step (not when it was replaced).
local function misfit_level(ctx)
  local s = ctx.sharp_disagreed
  if s and s > 0 then return s, ctx.sigma, false end
  local cand = ctx.sharp_candidate
  if not (cand and ctx.sharp_rejected and cand.sigma > 0) then return nil end
  return cand.sigma, cand.sigma, true
end

-- On the trusted points' path (the segment step read the pieces off them alone) the
-- smooth curve is judged at them, and the pieces are read off them and given back on every
-- point, as the segment step does: with or without down-weighted outliers among them, a
-- section swaps to the same pieces and the same curve.
local function pieces_for_misfit(P, ctx)
  if not M.allowed(ctx) or ctx.distances_of ~= ctx.fit then return nil end
  local s, unit, lenient = misfit_level(ctx)
  if not s then return nil end
  local t = common.trusted(ctx)
  local worst = t and common.trusted_max(ctx.distances, t, 1) or ctx.distances:max()
  if not (worst > MISFIT * unit) then return nil end
  local pieces, _, found = noisy.at(t and t.points or P, s, ctx.sigma, common.closed(ctx), lenient)
  if not pieces or not (found.max < worst) then return nil end
  common.warn(ctx, ("the smooth curve missed a sample by %.3g sigma: fitted the lines and arcs at "
    .. "noise %.3g (%s)"):format(worst / unit, s, ctx.sharp_rejected))
  if t then pieces = sharp.spread(pieces, trusted_indices(t), #P, common.closed(ctx)) end
  ctx.segment, ctx.segment_sigma, ctx.sharp_rejected = pieces, s, nil
  ctx.corners = sharp.corner_samples(P, pieces)
  return found.curve
end

-- The one curve of the pieces (bsfit.strategy.sharp): exact lines and arcs, free runs
-- fitted between them, joined; false when the section is fitted as one smooth curve.
function M.assemble(P, ctx)
  if not M.taken(ctx) then
    local C = pieces_for_misfit(P, ctx)
    if not C then return false end
    ctx.count = C:distinct()
    return C
  end
  local C = ctx.sharp_curve or sharp.assemble(P, ctx.segment, M.assembly(ctx, ctx.segment_sigma))
  ctx.count = C:distinct()
  return C
end

return M
