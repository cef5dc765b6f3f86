-- lua/bsfit/strategy/noisy_pieces.lua
-- When the lines, arcs and free runs of a noisy section are used instead of one smooth
-- curve (the `auto` strategy's `segment` step; docs/auto.md, "When the pieces are used"):
--
--   local noisy = require "bsfit.strategy.noisy_pieces"
--   local pieces, why, found = noisy.find(P, sigma, closed)
--
-- sigma is the window estimate of the noise (bs.geom.noise_sigma). pieces is nil when the
-- section is a smooth curve, why then says which test refused it (rep.pieces_rejected);
-- found.sigma is the noise read off the pieces, found.curve their one curve (found.max its
-- largest distance to a sample), and
-- found.candidate the segmentation before the tests (the loops step falls back on it);
-- found.disagreed, when the two noises disagreed, the pieces' (the windows' when no level
-- of lines and arcs matched): auto tries the pieces at it when the smooth curve misses its
-- samples (noisy.at(P, s, sigma, closed): every test but that one; where they agreed but a
-- test of the screen refused them, noisy.at(P, s, sigma, closed, true): leniently).
--
-- The tests, in order:
--   - the noise read off the lines' and arcs' own residuals (bs.geom.segment_sigma) is
--     below AGREE times the window estimate (where it is above, windows explain the samples
--     better than lines and arcs: a smooth curve; where it is far below, the samples are
--     too sparse for windows);
--   - two pieces or more; lines and arcs hold 90% of the samples; every two models meet
--     (a bridge is allowed only between two lines that continue each other); no two
--     lines meet tangentially (a polygon drawn along a smooth curve);
--   - every corner turns by MIN_TURN degrees at least and is worth EVIDENCE sigma^2 over
--     one smooth curve through both its sides; weak corners among strong ones are softened
--     into bends (sharp.soften), a section of weak corners only is a smooth curve;
--   - pieces without any corner (lines and arcs meeting tangentially all round: a rounded
--     rectangle, or a smooth curve followed by tangent arcs) explain the samples at least
--     as well as the windows do (AGREE_NO_CORNER): a smooth shape's curvature changes
--     along its arcs and leaves them more residual than the windows, a made object's lines
--     and fillets leave none;
--   - no piece degenerate, no corner farther from its samples than the longest step;
--   - they make one curve (bs.curve.join), which stays within 6 sigma of every sample and
--     does not cross itself.
-- Pieces refused at the noise read off them are tried at the next two levels of the noise
-- search (M.find, RETRY_LEVELS).
-- The evidence of a corner (how much worse one smooth curve through both its sides explains
-- their samples, in sigma^2) is, without a corner, about chi-square with the two models'
-- one or two more parameters: above 14 one time in a thousand. The estimate of sigma from
-- a few sides may be low by a factor sqrt(2), hence 25; a corner that turns by 60 degrees
-- or more is not what a smooth curve sampled this sparsely does between two samples (a
-- star's valley turns less at each sample), and 14 suffices (EVIDENCE_STEEP).

local bs = require "bsfit"
local common = require "bsfit.strategy.common"
local sharp = require "bsfit.strategy.sharp"

local M = {}

local EVIDENCE, EVIDENCE_STEEP, STEEP, MIN_TURN, AGREE = 25, 14, 60, 15, 1.25
-- Pieces with no corner at all: their noise at most the windows'. Tangent arcs follow a
-- cam or an ellipse within the noise, 3 to 7 times farther from the truth than the smooth
-- curve: 1.25 let 18 of test_auto's 180 smooth sections through so, 1.0 lets 3 (ellipses
-- within the noise of a four-arc oval), and dense rounded rectangles and filleted polygons, whose
-- windows read their fillets' curvature jumps as noise, still pass.
local AGREE_NO_CORNER = 1.0
-- the noise read off the pieces, when it agrees with the windows'
local function noise_of_pieces(P, sigma, closed)
  if not (sigma > 0) then return nil, "no noise" end
  local s = common.ok("noise of the pieces",
                      bs.geom.segment_sigma(P, { closed = closed, max = AGREE * sigma }))
  if s == 0 then -- no level up to the cap where the lines' and arcs' residual matched it
    return nil, ("no noise level of lines and arcs up to %.3g (windows %.3g)"):format(AGREE * sigma, sigma)
  end
  if not (s < AGREE * sigma) then
    return nil, ("noise of the pieces %.3g, of windows %.3g"):format(s, sigma), s
  end
  return s
end

local function weak_corner(p)
  return p.turn < MIN_TURN or p.evidence < (p.turn >= STEEP and EVIDENCE_STEEP or EVIDENCE)
end

local function weak_message(pieces, i)
  return ("weak corner %d: turn %.3g evidence %.3g"):format(i, pieces[i].turn, pieces[i].evidence)
end

-- The weak corners left to soften where others are strong (a made object): all but those
-- where two lines of LINE_CORNER_SAMPLES samples or more meet at STEEP degrees or more in
-- a stretch no sample saw: the corner lies farther than UNSAMPLED sigma from the
-- step between the samples either side of it. Their evidence is weak because nothing
-- samples the corner's neighbourhood (uneven or sparse samples: an L of 5 uneven samples
-- per side at noise 3e-3 had corners worth 0.7 and 3 sigma^2, its nearest samples a fifth
-- of a side away), and a bend explains them as well; but the lines fix where they meet,
-- and the bend cut the corner by several times the floor. Where samples do lie near the
-- corner and still cannot confirm it, it is softened as before (without that condition an
-- airfoil of 400 samples at noise 1e-3, read as pieces, got a second corner). Kept as
-- corners, the sweep gained 7 sections (227 -> 234 of 390), 780 sections on other seeds 8
-- (449 -> 457) and 780 denser ones 8 (635 -> 643); 400 smooth ones are unchanged.
local LINE_CORNER_SAMPLES, UNSAMPLED = 4, 3
-- two lines of LINE_CORNER_SAMPLES samples or more meeting at STEEP degrees or more
local function steep_line_corner(pieces, i)
  local p, q = pieces[i], pieces[(i - 2) % #pieces + 1]
  return p.kind == "line" and q.kind == "line" and p.count >= LINE_CORNER_SAMPLES
         and q.count >= LINE_CORNER_SAMPLES and p.turn >= STEEP
end

local function unsampled_line_corner(P, pieces, i, s)
  if not steep_line_corner(pieces, i) then return false end
  local p, q, m = pieces[i], pieces[(i - 2) % #pieces + 1], #P
  local ax, ay = P:get((q.first - 1 + q.count - 1) % m + 1)
  local bx, by = P:get(p.first)
  local x, y = p.start[1], p.start[2]
  local dx, dy = bx - ax, by - ay
  local l2 = dx * dx + dy * dy
  local t = l2 > 0 and math.max(0, math.min(1, ((x - ax) * dx + (y - ay) * dy) / l2)) or 0
  local ex, ey = ax + t * dx - x, ay + t * dy - y
  return math.sqrt(ex * ex + ey * ey) > UNSAMPLED * s
end

local function unconfirmed(P, pieces, weak, s)
  local out = {}
  for _, i in ipairs(weak) do
    if not unsampled_line_corner(P, pieces, i, s) then out[#out + 1] = i end
  end
  return out
end

-- Is the bridge pieces[i] (a free piece of no samples) allowed? Between two lines that
-- continue each other; leniently, also where its chord is at most BRIDGE_REACH times the
-- longest step between samples: a bridge spans a stretch no sample saw, and one longer than
-- the samples' own gaps joins two models extrapolated far past their samples (an L of 3
-- samples per side at noise 1e-3 bridged 0.93 of its longest step: 14 -> 37 times the
-- floor; of 41 lenient swaps with bridges on sparse sweeps of other seeds, the 6 that went
-- farther from the truth by more than 5% all bridged 0.65 to 0.93 of it).
-- (reach: BRIDGE_REACH times the longest step, or nil when not lenient)
local BRIDGE_REACH = 0.5
local function bridge_allowed(pieces, i, reach)
  if sharp.continues(pieces, i) then return true end
  if not reach then return false end
  local p = pieces[i]
  return math.sqrt((p.start[1] - p["end"][1]) ^ 2 + (p.start[2] - p["end"][2]) ^ 2) <= reach
end

-- What the pieces hold and how they meet: the indices of the weak corners, or nil and why.
-- s: the noise read off the pieces, sigma: the windows'.
local function screen(P, pieces, s, sigma, lenient)
  local held, weak, strong = 0, {}, 0
  local reach = lenient and BRIDGE_REACH * bs.geom.longest_step(P) or nil
  for i, p in ipairs(pieces) do
    local q = pieces[(i - 2) % #pieces + 1]
    if p.kind ~= "free" then held = held + p.count end
    if p.kind == "free" and p.count == 0 and not bridge_allowed(pieces, i, reach) then
      return nil, "bridge"
    end
    if p.join == "corner" then
      if weak_corner(p) then weak[#weak + 1] = i else strong = strong + 1 end
    end
    if p.join == "tangent" and p.kind == "line" and q.kind == "line" then
      return nil, "tangent lines"
    end
  end
  if held < 0.9 * #P then return nil, ("held %d of %d"):format(held, #P) end
  -- corners the data do not confirm: where others are (a made object), each is softened
  -- into a bend (below); where none is, the section is a smooth curve
  if #weak > 0 and strong == 0 then return nil, weak_message(pieces, weak[1]) end
  weak = unconfirmed(P, pieces, weak, s)
  -- no corner at all: the pieces must explain the samples as well as the windows
  if strong == 0 and not (s <= AGREE_NO_CORNER * sigma) then
    return nil, ("no corner, and the noise of the pieces %.3g is above the windows' %.3g"):format(s, sigma)
  end
  return weak
end

-- two lines meet at the corner where pieces[i] starts
local function line_corner(pieces, i)
  return pieces[i].kind == "line" and pieces[(i - 2) % #pieces + 1].kind == "line"
end

-- the pieces with each weak corner softened into a bend (sharp.soften), or nil and why;
-- lenient: a corner of two lines whose sides are too short to soften stays a corner
local function softened(P, pieces, weak, lenient)
  for k = #weak, 1, -1 do
    local soft = sharp.soften(P, pieces, weak[k])
    if not soft and not (lenient and line_corner(pieces, weak[k])) then
      return nil, weak_message(pieces, weak[k])
    end
    pieces = soft or pieces
  end
  return pieces
end

-- The weak corners between two steep lines whose bend, drawn, passes farther than UNSAMPLED
-- sigma from them are kept too: the test above measures the step between the samples
-- either side, but the bend is drawn tangent to both lines from one sample farther back
-- and cuts a corner more than that step does (a T with serifs of 6 samples per side at
-- noise 1e-3: a corner of 92 degrees worth 9.9 sigma^2, its step 3 sigma from it, its bend
-- 4.3). Returns the weak corners left to soften, and the softened pieces' curve when it
-- was assembled (curve_within_noise need not make it again).
local function bends_within(P, pieces, weak, soft, s, closed)
  local steep = {}
  for k, i in ipairs(weak) do
    if steep_line_corner(pieces, i) then steep[#steep + 1] = k end
  end
  if #steep == 0 then return weak end
  local made, C = pcall(sharp.assemble, P, soft, { closed = closed, sigma = s })
  if not made then return weak end -- refused below, as the pieces make no curve
  local out, cut = {}, {}
  for _, k in ipairs(steep) do
    local x = pieces[weak[k]].start
    local _, d = C:closest(x[1], x[2])
    if d > UNSAMPLED * s then cut[k] = true end
  end
  for k, i in ipairs(weak) do
    if not cut[k] then out[#out + 1] = i end
  end
  return out, C
end

-- the pieces with their weak corners softened but those bends_within keeps, or nil and
-- why; and their curve when bends_within assembled it
local function soften(P, pieces, weak, s, closed, lenient)
  local soft, why = softened(P, pieces, weak, lenient)
  if not soft then return nil, why end
  local left, C = bends_within(P, pieces, weak, soft, s, closed)
  if #left == #weak then return soft, nil, C end
  return softened(P, pieces, left, lenient)
end

-- The one curve of the pieces and its largest distance to a sample, or nil and why: it
-- must stay within the noise of every sample (6 sigma), and pieces that cross (a short
-- noisy side read as an arc bulging over its neighbour) are no better than the smooth
-- path, which the loops step can still repair.
-- C: the pieces' curve when it is already made.
local function curve_within_noise(P, pieces, s, closed, C)
  -- pieces that do not make one curve (bs.curve.join raises where two do not meet) are
  -- refused like any other: the smooth path remains
  if not C then
    local made
    made, C = pcall(sharp.assemble, P, pieces, { closed = closed, sigma = s })
    if not made then return nil, "the pieces make no curve: " .. tostring(C) end
  end
  local dmax = sharp.distances(C, P, pieces):max()
  if dmax > 6 * s then return nil, ("curve %.3g sigma from a sample"):format(dmax / s) end
  if bs.geom.self_intersections(C, math.max(2000, 32 * C:distinct())) > 0 then
    return nil, "the pieces' curve crosses itself"
  end
  return C, dmax
end

-- The pieces at noise s (the noise read off them; sigma: the windows'), through every test
-- but the agreement of the two: pieces, why, found as M.find's. lenient (auto's swap where
-- the smooth curve misses its samples by 6 s, pieces a test of the screen refused): a
-- bridge no longer than half the longest step is allowed and a weak corner of two lines
-- too short to soften stays a corner.
function M.at(P, s, sigma, closed, lenient)
  local found, why = {}, nil
  local pieces = common.ok("segmentation", bs.geom.segment(P, { closed = closed, sigma = s }))
  -- one piece round a noisy section (a circle within the noise, a mesh's slice of a vase):
  -- the smooth curve follows it as well, and stays polynomial
  if #pieces < 2 then return nil, "one piece", found end
  found.candidate = { pieces = pieces, sigma = s }
  local weak
  weak, why = screen(P, pieces, s, sigma, lenient)
  if not weak then return nil, why, found end
  local made
  pieces, why, made = soften(P, pieces, weak, s, closed, lenient)
  if not pieces then return nil, why, found end
  why = sharp.degenerate(pieces) or sharp.far_corner(P, pieces)
  if why then return nil, why, found end
  local C, r = curve_within_noise(P, pieces, s, closed, made)
  if not C then return nil, r, found end
  found.sigma, found.curve, found.max = s, C, r
  return pieces, nil, found
end

-- The noise search (bs.geom.segment_sigma) takes the first level whose pooled residual
-- matches it; on a sparse section the window of matching levels is narrow, and its first
-- level can be one at which the cover is wrong (a gear's tip arcs of 9 samples read at
-- 1.4 times the true noise as lines that meet nowhere). Where the pieces at that level are
-- refused, the next RETRY_LEVELS levels of the search's step (10^(1/4)) are tried, each
-- through every test, while they stay under the windows' agreement (AGREE): the first
-- that passes is taken. The sweep went from 237 to 241 sections within the floor, 780 on
-- other seeds from 469 to 479, none lost; 600 smooth noisy sections are unchanged.
-- Where those are refused too and the pieces at the search's level show a strong corner (a
-- made object's), the level below it (10^(1/4) lower) is tried: at the first level that
-- matches a model can take a sample of its neighbour (a bridge, a weak corner), and the
-- tighter tolerance below keeps the sides apart. Sweeps of other draws gained 10 of 2340
-- sections within the floor (2 went farther: an E of 4 samples per side at noise 1e-3 from
-- 13.6 to 15.6 times it, a gear of 6 at 1e-4 from 0.68 to 2.1), 624 sparse ones 427 -> 431
-- (a keyhole of 4 uneven samples per side at 1e-3 from 27 to 2.4 times the floor), the
-- sweep 252 -> 253. Without the strong corner, smooth shapes passed as tangent arcs there
-- (circles of 24 to 60 samples farther from the truth, an ellipse of 24 at 1e-2 with
-- corners); with it, 840 smooth sections are unchanged.
local RETRY_LEVELS, LEVEL_STEP = 2, bs.geom.SEGMENT_SIGMA_STEP

-- a corner of STEEP degrees or more worth EVIDENCE sigma^2 among the candidate's pieces
local function strong_corner(candidate)
  for _, p in ipairs(candidate and candidate.pieces or {}) do
    if p.join == "corner" and p.turn >= STEEP and p.evidence >= EVIDENCE then return true end
  end
  return false
end

function M.find(P, sigma, closed)
  local s, why, disagreed = noise_of_pieces(P, sigma, closed)
  if not s then return nil, why, { disagreed = disagreed or sigma } end
  local pieces, found
  pieces, why, found = M.at(P, s, sigma, closed)
  local level = s
  for _ = 1, RETRY_LEVELS do
    if pieces then break end
    level = level * LEVEL_STEP
    if not (level < AGREE * sigma) then break end
    local p2, _, f2 = M.at(P, level, sigma, closed)
    if p2 then return p2, nil, f2 end
  end
  if not pieces and strong_corner(found.candidate) then
    local p3, _, f3 = M.at(P, s / LEVEL_STEP, sigma, closed)
    if p3 then return p3, nil, f3 end
  end
  return pieces, why, found
end

return M
