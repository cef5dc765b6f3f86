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
--   ends     open or closed from the data when the setting closed = "auto" (default)
--   sigma    noise level normal to the curve, from the data alone (bs.geom.noise_sigma)
--   segment  lines, circular arcs and free runs (bs.geom.segment) when they explain the
--            section: exactly, or within the noise they show (bsfit.strategy.sharp);
--            {} otherwise. When it finds them, `assemble` makes the curve and the
--            smooth-fit steps below (params .. fit) stand aside
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
--            they touch, C0 at corners (false when there are no pieces)
--   reweight optional Huber reweighting, run when the setting robust = true (a step
--            and a setting cannot share a name: opts[step] replaces the step)
--   loops    self-intersection check of closed curves; refit with fewer control points
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
local anchors = require "bsfit.strategy.anchors"
local noisy = require "bsfit.strategy.noisy_pieces"

local M = { name = "auto" }

M.settings = { degree = 3, param = "chord", closed = "auto", trust = 0.1, correct = 3,
               robust = false, huber = 1.345, solver = "auto" }
M.optional = { point_weights = true, tol = true, count_max = true }

M.order = { "ends", "sigma", "segment", "params", "weights", "corners", "count", "fit",
            "assemble", "reweight", "loops", "measure" }

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

local size_of, count_range, gap_decision, doubt_closure

-- Adds a warning for rep.warnings.
local function warn(ctx, msg)
  ctx.warnings = ctx.warnings or {}
  ctx.warnings[#ctx.warnings + 1] = msg
end

-- May the pieces make the curve? Not when a step they would bypass was replaced or a count
-- or tolerance was asked for.
local function pieces_allowed(ctx)
  local o = ctx.opts
  return o.count == nil and o.corners == nil and o.fit == nil and ctx.settings.tol == nil
end

-- Is the section made into one curve of lines, arcs and free runs (the segment step
-- found features), rather than fitted as one smooth curve?
local function sharp_path(ctx)
  return type(ctx.segment) == "table" and #ctx.segment > 0 and pieces_allowed(ctx)
end


-- The samples' parameters as a Lua array (cached while ctx.params is the same).
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
  if closed(ctx) then n = math.max(n, #ctx.corners * p + 1) end -- each corner takes p knots
  -- Anchors too few to give n control points' spans two each (a sparse spiral whose
  -- windows read its curvature as noise, 4 sigma apart, left 5 anchors of 21 samples for
  -- 8 control points, and the knot placement raised): the knots go on the samples'
  -- parameters (the parameters keep the anchors).
  local u, breaks = ctx.knot_params, ctx.knot_breaks
  if not u or #u < 2 * n then u, breaks = ctx.params, nil end
  breaks = breaks or ctx.corner_positions or ctx.corners
  if closed(ctx) then
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
  local o = { degree = ctx.settings.degree, knots = K, periodic = closed(ctx),
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

-- Large sections are read through a subsample of at most SUBSAMPLE points for the
-- noise level, the corners and the distances measured during the count search:
-- all three are local or statistical, and the fits themselves still use every point.
local SUBSAMPLE = 5000

-- every s-th point of P (s = ceil(#P / SUBSAMPLE)), or nil when P is not larger
local function thinned(P)
  if #P <= SUBSAMPLE then return nil end
  local t = {}
  for i = 1, #P, math.ceil(#P / SUBSAMPLE) do t[#t + 1] = { P:get(i) } end
  return bs.points.new(t)
end

-- ctx.sub = {P = Points, stride = s, u = its parameters (set later)} when #P > SUBSAMPLE
local function subsample(ctx, P)
  if ctx.sub ~= nil or #P <= SUBSAMPLE then return ctx.sub end
  ctx.sub = { P = thinned(P), stride = math.ceil(#P / SUBSAMPLE) }
  return ctx.sub
end

-- every s-th value of a Vector, as a Vector
local function every(v, s)
  local r = {} -- read only the values kept, not the whole section into a table
  for i = 1, #v, s do r[#r + 1] = v:get(i) end
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

-- The pieces of exact data (bs.geom.segment at sigma = 0), or nil. A large section is
-- screened on its subsample `sub` first: noisy data has no exact runs. `pieces`: the
-- segmentation already made (by the ends step), if any.
local function exact_pieces(P, ctx, sub, pieces)
  if not pieces and sub then
    local screen = common.ok("segmentation", bs.geom.segment(sub, { closed = closed(ctx) }))
    if not sharp.has_features(screen, #sub) then return nil end
  end
  pieces = pieces or common.ok("segmentation", bs.geom.segment(P, { closed = closed(ctx) }))
  return sharp.has_features(pieces, #P) and pieces or nil
end

-- The pieces of the trusted points t.points alone (down-weighted points are no samples of
-- a line or an arc), given back on all of P (sharp.spread); the free runs are then fitted
-- to every point with its weight. {} when the trusted points make no pieces.
local function trusted_pieces(P, ctx, t)
  if not t.points or t.n < 6 then return {} end
  local Q = t.points
  -- idx[j]: the index among all of the j-th trusted point, found when asked (spread asks
  -- once per piece; a table of every index was a loop over all points in Lua)
  local idx = setmetatable({}, { __index = function(_, j) return common.trusted_index(t, j) end })
  local pieces = exact_pieces(Q, ctx, thinned(Q))
  if pieces then ctx.segment_sigma = 0
  else
    local why, found
    pieces, why, found = noisy.find(Q, ctx.sigma, closed(ctx))
    ctx.sharp_rejected = why
    if found.candidate then
      ctx.sharp_candidate = { sigma = found.candidate.sigma,
        pieces = sharp.spread(found.candidate.pieces, idx, #P, closed(ctx)) }
    end
    if pieces then ctx.segment_sigma = found.sigma end
  end
  return pieces and sharp.spread(pieces, idx, #P, closed(ctx)) or {}
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
  local sub = subsample(ctx, P)
  local exact = exact_pieces(P, ctx, sub and sub.P, ctx.cache.exact_pieces)
  if exact then ctx.segment_sigma = 0; return exact end
  local pieces, why, found = noisy.find(P, ctx.sigma, closed(ctx))
  ctx.sharp_rejected, ctx.sharp_candidate = why, found.candidate -- for the loops step
  ctx.sharp_disagreed = found.disagreed -- for the assemble step (pieces_for_misfit)
  if pieces then ctx.segment_sigma, ctx.sharp_curve = found.sigma, found.curve end
  return pieces or {}
end

function steps.segment(P, ctx)
  local pieces = segment_pieces(P, ctx)
  -- a closure the ends step found clear by the spacing alone, which the pieces make only by
  -- running on far past both end samples (sharp.closure_unsampled): three sides of a
  -- quadrilateral, their gap like a step, closed as a triangle no sample saw
  if ctx.closing and closed(ctx) and not ctx.closed_ambiguous and #pieces > 1 and
     sharp.closure_unsampled(P, pieces) then
    doubt_closure(ctx, "; the pieces close it only past both end samples")
  end
  return pieces
end

function steps.params(P, ctx)
  if sharp_path(ctx) then return bs.params(P, ctx.settings.param, { closed = closed(ctx) }) end
  local u = anchors.params(P, ctx, nil, subsample(ctx, P))
  if u then return u end
  return common.ok("params", bs.params_trusted(P, ctx.settings.param, {
    closed = closed(ctx), weights = ctx.settings.point_weights, trust = ctx.settings.trust }))
end

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
-- however it is closed (by the spacing or by the pieces; see steps.ends).
local CLOSING_CLEAR = 1.5

-- Open or closed from the gap alone: closed, clear (see steps.ends). hmax: the longest step.
function gap_decision(P, gap, h, hmax)
  local m = #P
  if gap <= 1.5 * h then return true, gap <= CLOSING_CLEAR * hmax end
  if gap <= hmax then return true, false end
  if gap <= 2.5 * h then return math.max(turn(P, m - 1, m, 1), turn(P, m, 1, 2)) <= 100, false end
  return false, gap > 2.5 * hmax
end

-- Does the chord from the last sample to the first cross a step of the samples' polygon
-- in its middle (a tenth of it from either end at least), a step more than a tenth of the
-- samples (and 2) from either end? Crossings near the ends are a closed scan's overlap, or
-- noise (a sparse noisy rounded rectangle's closing step crosses its neighbour's).
local function chord_crosses(P)
  local m = #P
  local ax, ay = P:get(m)
  local bx, by = P:get(1)
  local cx, cy = bx - ax, by - ay
  local function side(x, y) return cx * (y - ay) - cy * (x - ax) end
  local skip = math.max(2, m // 10)
  local px, py = P:get(skip)
  local sp = side(px, py)
  for i = skip + 1, m - skip do
    local qx, qy = P:get(i)
    local sq = side(qx, qy)
    if (sp > 0 and sq < 0) or (sp < 0 and sq > 0) then
      -- the step crosses the chord's line at fraction f of the step: where along the chord?
      local f = sp / (sp - sq)
      local x, y = px + f * (qx - px), py + f * (qy - py)
      local along = ((x - ax) * cx + (y - ay) * cy) / (cx * cx + cy * cy)
      if along > 0.1 and along < 0.9 then return true end
    end
    px, py, sp = qx, qy, sq
  end
  return false
end

-- The doubt of an open-or-closed decision the ends step made (ctx.closing): reported
-- (rep.closed_ambiguous) and said, with `why` (appended to the gap and steps).
function doubt_closure(ctx, why)
  local c = ctx.closing
  ctx.closed_ambiguous = true
  warn(ctx, ("open or closed is ambiguous (gap %.3g between the last and first points, steps "
    .. "%.3g near them%s): fitted %s; say --open or --closed"):format(c.gap, c.hloc, why,
    closed(ctx) and "closed" or "open"))
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
function steps.ends(P, ctx)
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
  if (not closed_ or not clear) and P:dim() == 2 and m >= 6 then
    local pieces, exact = sharp.closing_pieces(P, gap)
    if pieces then
      closed_ = true
      clear = gap <= CLOSING_CLEAR * all[#all] and not sharp.closure_unsampled(P, pieces)
      if exact and P == all_points then ctx.cache.exact_pieces = pieces end
    end
  end
  -- a closing chord across the samples' own polygon closes no outline (a spiral's ends lie
  -- on different turns): open, with the doubt said
  local crossing = closed_ and P:dim() == 2 and gap > 1.5 * hmed and chord_crosses(P)
  if crossing then closed_, clear = false, false end
  ctx.settings.closed = closed_
  ctx.closing = { gap = gap, hloc = hloc } -- decided here (see doubt_closure)
  if not clear then
    doubt_closure(ctx, crossing and "; closing it would cross the samples' own path" or "")
  end
  return closed_ and "closed" or "open"
end

function steps.sigma(P, ctx)
  if #P < 6 then return 0 end
  -- the noise of the trusted points (a gross outlier of weight 1e-3 is not noise)
  local t, sub = common.trusted(ctx), subsample(ctx, P)
  local Q = t and t.points and t.n >= 6 and t.points or nil
  Q = Q and (thinned(Q) or Q) or (sub and sub.P or P)
  local sigma, msg, code = bs.geom.noise_sigma(Q, { closed = closed(ctx) })
  if not sigma and code == "EDEGENERATE" then
    -- too few distinct points to estimate from (6 samples of a circle, repeats): they are
    -- followed as exact data, and the report says so
    warn(ctx, "too few distinct points to estimate the noise: the points are taken as exact")
    return 0
  end
  return common.ok("noise estimate", sigma, msg, code)
end

function steps.weights(P, ctx)
  local pw = ctx.settings.point_weights
  if pw == nil then return bs.weights.uniform(P) end
  if type(pw) == "table" then pw = bs.vector.new(pw) end
  if #pw ~= #P then error(("auto: point_weights has %d values for %d points"):format(#pw, #P), 0) end
  return pw
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

function steps.corners(P, ctx)
  if sharp_path(ctx) then return sharp.corner_samples(P, ctx.segment) end
  if not closed(ctx) or #P < 12 then anchors.knots(ctx); return {} end
  local o = { closed = true }
  if ctx.sigma > 0 then o.sigma = ctx.sigma end
  local sub = subsample(ctx, P)
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
    ctx.params = anchors.params(P, ctx, forced, subsample(ctx, P)) or ctx.params
  end
  if #fpos > 0 then
    ctx.params = common.ok("corner parameters", bs.params_through_corners(P, ctx.params,
      bs.vector.new(fpos), bs.points.new(fpts), ctx.settings.param, { closed = true }))
  end
  anchors.knots(ctx, spos)
  return as_table(idx)
end

-- The smallest and largest counts the search may try.
function count_range(P, ctx)
  local m, p = #P, ctx.settings.degree
  local nmin = math.max(p + 1, closed(ctx) and (#ctx.corners * p + 4) or 0, math.min(8, m // 2))
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
function size_of(P)
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

function steps.count(P, ctx)
  if sharp_path(ctx) then return 0 end -- the assemble step's
  local m = #P
  local n, nmax = count_range(P, ctx)
  local tol, sigma = ctx.settings.tol, ctx.sigma
  local floor = 1e-7 * size_of(P) -- clean data: no need to go below a relative 1e-7
  local tries, best, chosen, stalls, prev = {}, nil, nil, 0, nil
  while true do
    local C, u, d, N, wm, mfit = fit_corrected(ctx, P, n, ctx.sub and 0 or 1, ctx.sub ~= nil)
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
function steps.fit(P, ctx)
  if sharp_path(ctx) then return false end -- the assemble step's
  -- on large sections one correction round does nearly all the good (and each costs a
  -- projection of every point)
  local rounds = ctx.settings.correct
  if ctx.sub then rounds = math.min(rounds, 1) end
  local C, u, d = fit_corrected(ctx, P, ctx.count, rounds)
  ctx.params_final, ctx.distances, ctx.distances_of = u, d, C
  return C
end

-- The options of sharp.assemble: the free runs fitted to the trusted points with their
-- weights, at noise level sigma.
local function assembly(ctx, sigma)
  local pw, t = ctx.settings.point_weights, common.trusted(ctx)
  return { closed = closed(ctx), sigma = sigma or 0, weights = pw and as_table(pw) or nil,
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
-- step's untrusted path only (not when it was replaced, nor on the trusted points' path).
local function misfit_level(ctx)
  local s = ctx.sharp_disagreed
  if s and s > 0 then return s, ctx.sigma, false end
  local cand = ctx.sharp_candidate
  if common.trusted(ctx) or not (cand and ctx.sharp_rejected and cand.sigma > 0) then
    return nil
  end
  return cand.sigma, cand.sigma, true
end

local function pieces_for_misfit(P, ctx)
  if not pieces_allowed(ctx) or ctx.distances_of ~= ctx.fit then return nil end
  local s, unit, lenient = misfit_level(ctx)
  local worst = ctx.distances:max()
  if not (s and worst > MISFIT * unit) then return nil end
  local pieces, _, found = noisy.at(P, s, ctx.sigma, closed(ctx), lenient)
  if not pieces or not (found.max < worst) then return nil end
  warn(ctx, ("the smooth curve missed a sample by %.3g sigma: fitted the lines and arcs at "
    .. "noise %.3g (%s)"):format(worst / unit, s, ctx.sharp_rejected))
  ctx.segment, ctx.segment_sigma, ctx.sharp_rejected = pieces, s, nil
  ctx.corners = sharp.corner_samples(P, pieces)
  return found.curve
end

-- The one curve of the pieces (bsfit.strategy.sharp): exact lines and arcs, free runs
-- fitted between them, joined; false when the section is fitted as one smooth curve.
function steps.assemble(P, ctx)
  if not sharp_path(ctx) then
    local C = pieces_for_misfit(P, ctx)
    if not C then return false end
    ctx.count = C:distinct()
    return C
  end
  local C = ctx.sharp_curve or sharp.assemble(P, ctx.segment, assembly(ctx, ctx.segment_sigma))
  ctx.count = C:distinct()
  return C
end

-- Optional Huber reweighting: points farther than huber x sigma from the curve get
-- weight w c/|d|; three rounds.
function steps.reweight(P, ctx)
  if not ctx.settings.robust or sharp_path(ctx) then return ctx.curve end
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

-- A smooth curve that still crosses itself, when lines and arcs within the noise were
-- found but one of their corners fell short of the evidence: the curve of the pieces,
-- when it does not cross itself and stays within 6 sigma of every sample, is the better
-- answer (a loop is a defect; a weakly supported corner only a doubt), said in a warning.
-- Returns 0 then, else nil.
local function loop_free_pieces(P, ctx, k)
  local alt = ctx.sharp_candidate
  if sharp.degenerate(alt.pieces) or #alt.pieces < 2 then return nil end
  for _, p in ipairs(alt.pieces) do if p.kind == "free" and p.count == 0 then return nil end end
  local C = sharp.assemble(P, alt.pieces, assembly(ctx, alt.sigma))
  if bs.geom.self_intersections(C, k) > 0 then return nil end
  if sharp.distances(C, P, alt.pieces):max() > 6 * alt.sigma then return nil end
  ctx.segment, ctx.segment_sigma, ctx.curve = alt.pieces, alt.sigma, C
  ctx.corners, ctx.count = sharp.corner_samples(P, alt.pieces), C:distinct()
  warn(ctx, "the smooth curve crossed itself: fitted the lines and arcs instead (a corner of "
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
  local C, rep = M.run(P, o)
  if rep.crossings > 0 then return nil end
  ctx.curve, ctx.corners, ctx.count, ctx.tries = C, {}, rep.count, rep.tries
  ctx.params_final, ctx.distances, ctx.distances_of = nil, nil, nil
  warn(ctx, "the curve with sharp corners crossed itself: fitted without them")
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
function steps.loops(P, ctx)
  local C = ctx.curve
  if not closed(ctx) or P:dim() ~= 2 then return 0 end
  local k = math.max(2000, 32 * C:distinct())
  local n, where = bs.geom.self_intersections(C, k)
  if n > 0 and not sharp_path(ctx) and ctx.opts.count == nil then
    local lo, hi = count_range(P, ctx)
    local tried = { [ctx.count] = true }
    for _, f in ipairs { 0.8, 0.64, 0.51, 1.25, 1.56 } do
      local c = math.max(lo, math.min(hi, math.floor(f * ctx.count + 0.5)))
      if not tried[c] then
        tried[c] = true
        local C2, u, d, N = fit_corrected(ctx, P, c, ctx.sub and 1 or ctx.settings.correct)
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
  if n > 0 and not sharp_path(ctx) and ctx.sharp_candidate then n = loop_free_pieces(P, ctx, k) or n end
  if n > 0 and not sharp_path(ctx) then n = without_corners(P, ctx) or n end
  if n > 0 then
    local turns = polygon_turns(P)
    warn(ctx, ("the curve crosses itself (%d crossing%s, first near parameter %.4g)%s"):format(
      n, n == 1 and "" or "s", where, turns >= 2 and (": the samples' polygon turns round %d "
      .. "times; are the samples in order along the outline?"):format(turns) or ""))
  end
  return n
end

function steps.measure(P, ctx)
  if sharp_path(ctx) then
    return common.measure_of(ctx, sharp.distances(ctx.curve, P, ctx.segment))
  end
  local d = ctx.distances -- the fit's last projection, when it is of this very curve
  if ctx.distances_of ~= ctx.curve or d == nil then
    d = select(2, ctx.curve:project(P, ctx.params_final or ctx.params, NEWTON))
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
  rep.closed = closed(ctx)
  rep.closed_ambiguous = ctx.closed_ambiguous or false
  rep.crossings = ctx.loops or 0
  if sharp_path(ctx) then rep.pieces, rep.pieces_sigma = ctx.segment, ctx.segment_sigma end
  rep.pieces_rejected = ctx.sharp_rejected
  -- warnings: appended to those the common report may already carry
  if ctx.warnings and #ctx.warnings > 0 then
    rep.warnings = rep.warnings or {}
    for _, w in ipairs(ctx.warnings) do rep.warnings[#rep.warnings + 1] = w end
  end
  return rep
end

return M
