-- lua/bsfit/strategy/loops.lua
-- Never a loop: the `loops` step of the auto strategy (docs/auto.md, "Never a loop"). A
-- closed 2D curve is checked for self-intersection and a crossing repaired (other counts,
-- the pieces instead, no corners) or reported.
--
--   local loops = require "bsfit.strategy.loops"
--   local n = loops.check(P, ctx)   -- crossings left; ctx.curve replaced by a repair

local bs = require "bsfit"
local common = require "bsfit.strategy.common"
local sharp = require "bsfit.strategy.sharp"
local smooth = require "bsfit.strategy.smooth_path"
local pieces = require "bsfit.strategy.pieces_path"

local M = {}

-- A smooth curve that still crosses itself, when lines and arcs within the noise were
-- found but one of their corners fell short of the evidence: the curve of the pieces,
-- when it does not cross itself and stays within 6 sigma of every sample, is the better
-- answer (a loop is a defect; a weakly supported corner only a doubt), said in a warning.
-- Returns 0 then, else nil.
local function loop_free_pieces(P, ctx, k)
  local alt = ctx.sharp_candidate
  if sharp.degenerate(alt.pieces) or #alt.pieces < 2 then return nil end
  for _, p in ipairs(alt.pieces) do if p.kind == "free" and p.count == 0 then return nil end end
  local C = sharp.assemble(P, alt.pieces, pieces.assembly(ctx, alt.sigma))
  if bs.geom.self_intersections(C, k) > 0 then return nil end
  if sharp.distances(C, P, alt.pieces):max() > 6 * alt.sigma then return nil end
  ctx.segment, ctx.segment_sigma, ctx.curve = alt.pieces, alt.sigma, C
  ctx.corners, ctx.count = sharp.corner_samples(P, alt.pieces), C:distinct()
  common.warn(ctx, "the smooth curve crossed itself: fitted the lines and arcs instead (a corner of "
    .. "theirs is weakly supported by the data)")
  return 0
end

-- The smooth path's own sharp corners (triple knots) can swing a sparse section round a
-- loop between them: when refits with other counts keep a crossing, the section is fitted
-- again without corners (the corners step replaced by {}), kept when that has none, and
-- said in a warning. Returns 0 then, else nil.
local function without_corners(P, ctx)
  if #ctx.corners == 0 or ctx.opts.corners ~= nil then return nil end
  local o = {}
  for key, v in pairs(ctx.opts) do o[key] = v end
  o.corners, o.closed = {}, true
  local C, rep = ctx.strategy.run(P, o)
  if rep.crossings > 0 then return nil end
  ctx.curve, ctx.corners, ctx.count, ctx.tries = C, {}, rep.count, rep.tries
  ctx.params_final, ctx.distances, ctx.distances_of = nil, nil, nil
  common.warn(ctx, "the curve with sharp corners crossed itself: fitted without them")
  return 0
end

-- How many times the polygon of the samples turns round (the sum of its signed turns over
-- 2 pi, rounded): 1 for an outline sampled in order, whatever its shape; many for samples
-- taken out of order (cos i, sin i for i = 1 .. 9119: a circle walked round 1451 times).
local function polygon_turns(P)
  local m, total = #P, 0
  local px, py = P:get(m)
  local qx, qy = P:get(1)
  local ux, uy = qx - px, qy - py
  for i = 1, m do
    local rx, ry = P:get(i % m + 1)
    local vx, vy = rx - qx, ry - qy
    if vx ~= 0 or vy ~= 0 then
      if ux ~= 0 or uy ~= 0 then total = total + math.atan(ux * vy - uy * vx, ux * vx + uy * vy) end
      ux, uy = vx, vy
    end
    qx, qy = rx, ry
  end
  return math.floor(math.abs(total) / (2 * math.pi) + 0.5)
end

-- Never a loop: a closed 2D curve is checked for self-intersection (a sweep over
-- max(2000, 32 n) samples in C: a loop at a corner can be a few thousandths of the curve
-- long). A smooth fit that crosses itself is refitted with fewer control points (0.8, 0.64,
-- 0.51 times), then with more (1.25, 1.56 times: too few can swing a sparse corner round),
-- the first without a crossing kept (else the one with fewest); a crossing that remains, or
-- one of the pieces' curve, is reported in rep.warnings and rep.crossings. Returns the
-- number of crossings.
function M.check(P, ctx)
  local C = ctx.curve
  if not common.closed(ctx) or P:dim() ~= 2 then return 0 end
  local k = math.max(2000, 32 * C:distinct())
  local n, where = bs.geom.self_intersections(C, k)
  if n > 0 and not pieces.taken(ctx) and ctx.opts.count == nil then
    local lo, hi = smooth.count_range(P, ctx)
    local tried = { [ctx.count] = true }
    for _, f in ipairs { 0.8, 0.64, 0.51, 1.25, 1.56 } do
      local c = math.max(lo, math.min(hi, math.floor(f * ctx.count + 0.5)))
      if not tried[c] then
        tried[c] = true
        local C2, u, d, N = smooth.fit_corrected(ctx, P, c, ctx.sub and 1 or ctx.settings.correct)
        local n2, w2 = bs.geom.self_intersections(C2, k)
        if n2 < n then
          C, n, where = C2, n2, w2
          ctx.curve, ctx.params_final, ctx.distances, ctx.distances_of = C2, u, d, C2
          ctx.count = N
        end
        if n == 0 then break end
      end
    end
  end
  if n > 0 and not pieces.taken(ctx) and ctx.sharp_candidate then n = loop_free_pieces(P, ctx, k) or n end
  if n > 0 and not pieces.taken(ctx) then n = without_corners(P, ctx) or n end
  if n > 0 then
    local turns = polygon_turns(P)
    common.warn(ctx, ("the curve crosses itself (%d crossing%s, first near parameter %.4g)%s"):format(
      n, n == 1 and "" or "s", where, turns >= 2 and (": the samples' polygon turns round %d "
      .. "times; are the samples in order along the outline?"):format(turns) or ""))
  end
  return n
end

return M
