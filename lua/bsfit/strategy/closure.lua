-- lua/bsfit/strategy/closure.lua
-- Open or closed from the data: the `ends` step of the auto strategy (docs/auto.md, "Open
-- or closed"), and the doubt it reports.
--
--   local closure = require "bsfit.strategy.closure"
--   local what = closure.decide(P, ctx)   -- "closed" or "open"; ctx.settings.closed set
--   closure.doubt(ctx, why)               -- rep.closed_ambiguous and a warning

local common = require "bsfit.strategy.common"
local sharp = require "bsfit.strategy.sharp"

local M = {}

-- degrees between the steps i -> j and j -> k of P
local function turn(P, i, j, k)
  local a, b, c = { P:get(i) }, { P:get(j) }, { P:get(k) }
  local dot, na, nb = 0, 0, 0
  for q = 1, #a do
    local u, v = b[q] - a[q], c[q] - b[q]
    dot, na, nb = dot + u * v, na + u * u, nb + v * v
  end
  if na == 0 or nb == 0 then return 0 end
  return math.deg(math.acos(math.max(-1, math.min(1, dot / math.sqrt(na * nb)))))
end

-- A closing gap longer than CLOSING_CLEAR times the longest other step leaves a doubt
-- however it is closed (by the spacing or by the pieces; see M.decide): the gap is then the
-- longest step of the polygon by a margin, as in an open run and in a closed section
-- sampled as unevenly. 1.5 closed open arcs with gaps of 1.2 to 1.5 steps without a doubt,
-- and 77 of 600 open parts of the sweep's outlines (53 at 1.2, 38 at 1.0); 1.0 doubted
-- evenly sampled closed sections (a circle of 24 exact samples), 1.2 the closed sections of
-- those 600 parts 26 times (20 at 1.5).
local CLOSING_CLEAR = 1.2

-- Open or closed from the gap alone: closed, clear (see M.decide). hmax: the longest step.
local function gap_decision(P, gap, h, hmax)
  local m = #P
  if gap <= 1.5 * h then return true, gap <= CLOSING_CLEAR * hmax end
  if gap <= hmax then return true, false end
  if gap <= 2.5 * h then return math.max(turn(P, m - 1, m, 1), turn(P, m, 1, 2)) <= 100, false end
  return false, gap > 2.5 * hmax
end

-- Is the path's segment from a along (cx, cy) (length len, the path's length before it
-- `before`, in all `total`) crossed by a step of P's polygon from sample skip to m - skip
-- in the path's middle tenths?
local function segment_crossed(P, skip, a, cx, cy, len, before, total)
  local function side(x, y) return cx * (y - a[2]) - cy * (x - a[1]) end
  local px, py = P:get(skip)
  local sp = side(px, py)
  for i = skip + 1, #P - skip do
    local qx, qy = P:get(i)
    local sq = side(qx, qy)
    if (sp > 0 and sq < 0) or (sp < 0 and sq > 0) then
      -- the step crosses the segment's line at fraction f of the step: where along it?
      local f = sp / (sp - sq)
      local x, y = px + f * (qx - px), py + f * (qy - py)
      local along = ((x - a[1]) * cx + (y - a[2]) * cy) / (len * len)
      local at = (before + along * len) / total
      if along >= 0 and along <= 1 and at > 0.1 and at < 0.9 then return true end
    end
    px, py, sp = qx, qy, sq
  end
  return false
end

-- Does the closing path (points from the last sample to the first: the chord between them,
-- or the way the closing pieces go round) cross a step of the samples' polygon in its
-- middle (a tenth of its length from either end at least), a step more than a tenth of
-- the samples (and 2) from either end? Crossings near the ends are a closed scan's overlap,
-- or noise (a sparse noisy rounded rectangle's closing step crosses its neighbour's).
local function path_crosses(P, path)
  local m, total = #P, 0
  local skip = math.max(2, m // 10)
  for k = 1, #path - 1 do
    total = total + math.sqrt((path[k + 1][1] - path[k][1]) ^ 2 + (path[k + 1][2] - path[k][2]) ^ 2)
  end
  if not (total > 0) then return false end
  local before = 0 -- the path's length before segment k
  for k = 1, #path - 1 do
    local a, b = path[k], path[k + 1]
    local cx, cy = b[1] - a[1], b[2] - a[2]
    local len = math.sqrt(cx * cx + cy * cy)
    if len > 0 and segment_crossed(P, skip, a, cx, cy, len, before, total) then return true end
    before = before + len
  end
  return false
end

-- The doubt of an open-or-closed decision the ends step made (ctx.closing): reported
-- (rep.closed_ambiguous) and said, with `why` (appended to the gap and steps).
function M.doubt(ctx, why)
  local c = ctx.closing
  ctx.closed_ambiguous = true
  common.warn(ctx, ("open or closed is ambiguous (gap %.3g between the last and first points, "
    .. "steps %.3g near them%s): fitted %s; say --open or --closed"):format(c.gap, c.hloc, why,
    common.closed(ctx) and "closed" or "open"))
end

-- Open or closed (setting closed = "auto", the default): from the gap between the last
-- and the first point against the steps next to them (the two at each end, h_loc: a
-- closed section's closing step is like its neighbours, while sections sampled sparsely
-- along long sides have steps far longer elsewhere) and twice the median step, h =
-- max(h_loc, 2 h_med). A gap up to 1.5 h closes the section, and so does one no longer
-- than the longest step elsewhere (samples spread unevenly along long sides leave steps of
-- half a side), as ambiguous; one above 2.5 h opens it, as ambiguous when it is within 2.5
-- times the longest step; between, the section is closed when the closing chord continues
-- both ends (turns by at most 100 degrees from the last step and into the first: an open
-- run's ends point away from each other), as ambiguous. Ambiguous decisions are reported
-- (rep.closed_ambiguous, a warning). Lines and arcs that cover the section
-- and meet across the gap without a detour (sharp.closing_pieces) close it, with a doubt
-- when they run on past both end samples into the gap far beyond their own steps
-- (sharp.closure_unsampled). A gap longer
-- than CLOSING_CLEAR times the longest other step leaves a doubt, however it is closed; a
-- closing chord that crosses the samples' own path (chord_crosses) opens the section,
-- with a doubt. closed = true or false is taken as given.
function M.decide(P, ctx)
  local c = ctx.settings.closed
  if c == true or c == false then return c and "closed" or "open" end
  if c ~= "auto" then
    error("bad argument #2 to 'run' (option 'closed' must be true, false or \"auto\")", 0)
  end
  -- the trusted points' ends (a down-weighted outlier last is not where the outline stops)
  local t, all_points = common.trusted(ctx, P), P
  if t and t.points and t.n >= 6 then P = t.points end
  local m = #P
  local function step(i, j)
    local a, b, d2 = { P:get(i) }, { P:get(j) }, 0
    for k = 1, #a do d2 = d2 + (a[k] - b[k]) ^ 2 end
    return math.sqrt(d2)
  end
  -- the steps between distinct points (repeated points take no part)
  local all = {}
  for i = 1, m - 1, math.max(1, (m - 1) // 2000) do -- at most ~2000 steps read
    local d = step(i, i + 1)
    if d > 0 then all[#all + 1] = d end
  end
  for _, i in ipairs { m - 2, m - 1 } do -- the last two steps, for h_loc
    if i >= 1 and (m - 1) > 2000 then
      local d = step(i, i + 1)
      if d > 0 then all[#all + 1] = d end
    end
  end
  if #all == 0 then ctx.settings.closed = true; return "closed" end -- coincident: the fit says so
  local hloc = math.max(all[1], all[math.min(2, #all)], all[#all], all[math.max(#all - 1, 1)])
  table.sort(all)
  local hmed = all[(#all + 1) // 2]
  local gap, h = step(m, 1), math.max(hloc, 2 * hmed)
  local closed_, clear = gap_decision(P, gap, h, all[#all])
  -- lines and arcs that meet across the gap close it; without a doubt when the gap is like
  -- the other steps (at most CLOSING_CLEAR times the longest): across a longer one, an open
  -- run's end sides may meet as well (three sides of a pentagon, an arc of 270 degrees)
  local path = { { P:get(m) }, { P:get(1) } } -- how the section would close
  if (not closed_ or not clear) and P:dim() == 2 and m >= 6 then
    local pieces, exact = sharp.closing_pieces(P, gap)
    if pieces then
      closed_ = true
      clear = gap <= CLOSING_CLEAR * all[#all] and not sharp.closure_unsampled(P, pieces)
      if exact and P == all_points then ctx.cache.exact_pieces = pieces end
      path = sharp.closing_path(P, pieces)
    end
  end
  -- a closing chord across the samples' own polygon closes no outline (a spiral's ends lie
  -- on different turns): open, with the doubt said. Where closing pieces were found, the
  -- way they go round is what must not cross (the chord of an E of 3 uneven samples per
  -- side, from the middle of its back to the middle of its foot, crossed its lower arm; the
  -- back and the foot meet at its corner: opened, it was 170 times the floor off)
  local crossing = closed_ and P:dim() == 2 and gap > 1.5 * hmed and path_crosses(P, path)
  if crossing then closed_, clear = false, false end
  ctx.settings.closed = closed_
  ctx.closing = { gap = gap, hloc = hloc } -- decided here (see M.doubt)
  if not clear then
    M.doubt(ctx, crossing and "; closing it would cross the samples' own path" or "")
  end
  return closed_ and "closed" or "open"
end

return M
