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
--   sigma    noise level normal to the curve, from the data alone (bs.geom.noise_sigma)
--   params   chord parameters over the trusted points (weight >= trust x median);
--            the others interpolated (bs.params_trusted). Where samples crowd closer
--            than the noise (clusters, a densely sampled trailing edge), chords measure
--            the noise, not the contour: the parameters then run along "anchors" at
--            least 4 sigma apart (on the path smoothed over 5 samples), the samples
--            between two anchors placed by their projection on the anchors' chord, and
--            the knots are placed on the anchors, so a cluster gets neither parameter
--            length nor knots of its own (it would loop)
--   weights  the file's weights (point_weights), else 1
--   corners  sharp corners (bs.geom.corners); a triple knot is put at each, and
--            the knots next to it are kept far enough along its sides for their
--            control points to read the sides' directions off more than noise
--   count    the search: counts grow geometrically from a small start, each fit's
--            parameters corrected once, until the weighted RMS distance reaches the
--            noise level (or stops improving near it, or near it a step buys no more
--            than fitting noise would); `tol` asks for a maximum distance instead
--   fit      the final fit: `correct` rounds of parameter correction (foot points)
--   reweight optional Huber reweighting, run when the setting robust = true (a step
--            and a setting cannot share a name: opts[step] replaces the step)
--   measure  distances of the points to the curve (vectorised projection in C)
-- Settings: degree (3), param ("chord"), closed (true), trust (0.1), correct (3),
-- robust (false), huber (1.345), solver ("auto": Cholesky, QR when the normal matrix
-- is ill-conditioned; see bs.fitter), count_max (m/2 up to 500 points, then m/3, at
-- most 4000); optional:
-- point_weights, tol.
-- rep: count, sigma, corners (1-based indices), tries ({count, rms, max} per fit of
-- the search), rms, max, max_index, residuals (distances), times per step.

local bs = require "bsfit"
local common = require "bsfit.strategy.common"

local M = { name = "auto" }

M.settings = { degree = 3, param = "chord", closed = true, trust = 0.1, correct = 3,
               robust = false, huber = 1.345, solver = "auto" }
M.optional = { point_weights = true, tol = true, count_max = true }

M.order = { "sigma", "params", "weights", "corners", "count", "fit", "reweight", "measure" }

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

local knots_on_anchors

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
    knots_on_anchors(ctx, ctx.corner_positions or ctx.corners)
  end
  local u = ctx.knot_params or ctx.params
  if closed(ctx) then
    n = math.max(n, #ctx.corners * p + 1) -- each corner takes p knots
    local K, N = common.ok("knots", bs.knots.breaks { params = u, degree = p, count = n,
      breaks = ctx.knot_breaks or ctx.corner_positions or ctx.corners })
    return widen_corner_spans(ctx, ctx.P, K, N)
  end
  return common.ok("knots", bs.knots.averaging { params = u, count = n, degree = p,
                                                 closed = false }), n
end

-- One fit with knots K on parameters u; reuses the strategy's fitter.
local function fit_once(ctx, P, K, u, w)
  local o = { degree = ctx.settings.degree, knots = K, periodic = closed(ctx),
              solver = ctx.settings.solver }
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
  local r = {} -- read only the values kept, not the whole section into a table
  for i = 1, #v, s do r[#r + 1] = v:get(i) end
  return bs.vector.new(r)
end

-- {======================================================================
-- Anchors: parameters that samples closer than the noise cannot stretch
-- =======================================================================

local ANCHOR = 4 -- anchors at least ANCHOR sigma apart: a chord across 4 sigma of contour
                 -- is stretched by the noise of its two ends by ~12%, a chord across less
                 -- than sigma is mostly noise

-- The path the anchors are read from: each point replaced by the mean of the (trusted)
-- points within two samples of it, so that a blob of samples under noise stays put
-- instead of hopping about by a few sigma (it would make anchors of its own).
-- Returns arrays x, y, z (z nil in 2D).
local function smooth_path(px, py, pz, is_closed, skip)
  local m = #px
  local x, y, z = {}, {}, #pz > 0 and {} or nil
  if not skip and is_closed and m >= 5 then
    -- a sliding sum of five
    local sx = px[m - 1] + px[m] + px[1] + px[2] + px[3]
    local sy = py[m - 1] + py[m] + py[1] + py[2] + py[3]
    local sz = z and (pz[m - 1] + pz[m] + pz[1] + pz[2] + pz[3]) or 0
    for i = 1, m do
      x[i], y[i] = sx / 5, sy / 5
      if z then z[i] = sz / 5 end
      local out, inn = (i - 3) % m + 1, (i + 2) % m + 1
      sx, sy = sx - px[out] + px[inn], sy - py[out] + py[inn]
      if z then sz = sz - pz[out] + pz[inn] end
    end
    return x, y, z
  end
  for i = 1, m do
    local sx, sy, sz, n = 0, 0, 0, 0
    for o = -2, 2 do
      local j = i + o
      if is_closed then j = (j - 1) % m + 1 end
      if j >= 1 and j <= m and not (skip and skip[j]) then
        sx, sy, n = sx + px[j], sy + py[j], n + 1
        if z then sz = sz + pz[j] end
      end
    end
    if n == 0 then sx, sy, sz, n = px[i], py[i], pz[i] or 0, 1 end
    x[i], y[i] = sx / n, sy / n
    if z then z[i] = sz / n end
  end
  return x, y, z
end

-- Indices (increasing) of the anchors on the path x, y, z: the first point, then each
-- at least delta from the previous anchor; `forced` ({[i] = true}) always are, points
-- with skip[i] never are (untrusted). Closed data: the last anchor must also be delta
-- from the first; open data: the last point is one.
local function find_anchors(x, y, z, delta, is_closed, skip, forced)
  local m = #x
  local idx, a = { 1 }, 1
  local d2 = delta * delta
  local function far(i, j)
    return (x[i] - x[j]) ^ 2 + (y[i] - y[j]) ^ 2 + (z and (z[i] - z[j]) ^ 2 or 0) >= d2
  end
  for i = 2, m do
    if (forced and forced[i]) or (not (skip and skip[i]) and far(i, a)) then
      idx[#idx + 1] = i; a = i
    end
  end
  if is_closed and #idx > 1 and not (forced and forced[idx[#idx]]) and not far(1, a) then
    idx[#idx] = nil
  elseif not is_closed and idx[#idx] ~= m then
    idx[#idx + 1] = m
  end
  return idx
end

-- Do the anchors matter? Only where far more samples crowd between two anchors than
-- between most (clusters, a densely sampled trailing edge): where every gap holds about
-- as many, noise inflates every chord alike, and chord parameters are left alone
-- (they also keep knots denser where the samples are, which often follows the shape).
local function anchors_matter(idx, m, is_closed)
  local n, gaps = #idx, {}
  if n < 4 or n >= m then return false end
  for r = 1, n - 1 do gaps[r] = idx[r + 1] - idx[r] end
  if is_closed then gaps[n] = m + idx[1] - idx[n] end
  local sorted = table.move(gaps, 1, #gaps, 1, {})
  table.sort(sorted)
  return sorted[#sorted] > 4 * sorted[(#sorted + 1) // 2] + 2
end

-- Parameters (a Lua array over the path's points) from the anchors idx: chord (or
-- centripetal) lengths between anchors along the path; a point between two anchors
-- goes by how far along their chord it projects, never back (the parameters must not
-- decrease). By index it would not do: a cluster of many samples next to one anchor
-- would take most of the gap from the few that cover it.
local function anchored_params(x, y, z, idx, kind, is_closed)
  local m, n = #x, #idx
  local ua, acc = { 0 }, 0
  local function chord(i, j)
    local d = math.sqrt((x[i] - x[j]) ^ 2 + (y[i] - y[j]) ^ 2 + (z and (z[i] - z[j]) ^ 2 or 0))
    return kind == "centripetal" and math.sqrt(d) or d
  end
  for r = 2, n do acc = acc + chord(idx[r], idx[r - 1]); ua[r] = acc end
  local total = acc
  if is_closed then total = acc + chord(idx[1], idx[n]) end
  if not (total > 0) then return nil end
  local u = {}
  for r = 1, n do
    local a, ub = idx[r], (r < n and ua[r + 1] or total)
    local b = r < n and idx[r + 1] or (is_closed and m + idx[1] or a)
    local u0 = ua[r]
    u[a] = u0 / total
    if b > a + 1 then
      local bb = (b - 1) % m + 1
      local dx, dy, dz = x[bb] - x[a], y[bb] - y[a], z and z[bb] - z[a] or 0
      local dd, tmax = dx * dx + dy * dy + dz * dz, 0
      for i = a + 1, b - 1 do
        local ii = (i - 1) % m + 1
        local t = (i - a) / (b - a)
        if dd > 0 then
          t = ((x[ii] - x[a]) * dx + (y[ii] - y[a]) * dy + (z and (z[ii] - z[a]) * dz or 0)) / dd
          t = math.min(math.max(t, tmax), 1)
          tmax = t
        end
        u[ii] = (u0 + (ub - u0) * t) / total
      end
    end
  end
  -- closed: never exactly 1 (the period is [0, 1))
  if is_closed then
    local below1 = 1 - 2 ^ -52
    for i = 1, m do if u[i] >= 1 then u[i] = below1 end end
  end
  return u
end

-- The anchors of the section (ctx.anchors = indices into P) when they matter, read
-- from P itself or, for a large section, from its subsample (whose parameters are then
-- interpolated by index to the points between); `forced` adds indices of P that must
-- be anchors (the samples around a corner; subsample points for a large section).
-- Returns the parameters (Vector), or nil.
local function anchor_params(P, ctx, forced)
  local s = ctx.settings
  if not (ctx.sigma and ctx.sigma > 0) or s.param == "uniform" or #P < 12 then return nil end
  local delta, is_closed = ANCHOR * ctx.sigma, closed(ctx)
  local trusted = common.trusted(ctx)
  local sub = subsample(ctx, P)
  local W, st = sub and sub.P or P, sub and sub.stride or 1
  local skip
  if trusted then
    -- the untrusted points (common.trusted lists them, or masks the trusted ones)
    local out = trusted.out
    if not out then
      out = {}
      for i, ok in ipairs(trusted.mask) do if not ok then out[#out + 1] = i end end
    end
    skip = {}
    for _, i in ipairs(out) do
      if i == 1 then return nil end -- the parameters start at a trusted point
      if (i - 1) % st == 0 then skip[(i - 1) // st + 1] = true end
    end
  end
  local wforced
  if forced then
    wforced = {}
    for i in pairs(forced) do wforced[(i - 1) // st + 1] = true end
    for _, i in ipairs(ctx.anchors) do wforced[(i - 1) // st + 1] = true end
  end
  -- A gap between anchors holds many samples only where samples 6 apart are within
  -- delta of each other: without any, nothing to do (the common case, checked first).
  local mw, px, py, pz = #W, {}, {}, {}
  for i = 1, mw do px[i], py[i], pz[i] = W:get(i) end
  if not forced then
    local crowded, d2 = false, delta * delta
    for i = 1, mw - 6 do
      local j = i + 6
      if (px[j] - px[i]) ^ 2 + (py[j] - py[i]) ^ 2 + (pz[i] and (pz[j] - pz[i]) ^ 2 or 0) < d2 then
        crowded = true
        break
      end
    end
    if not crowded then return nil end
  end
  local x, y, z = smooth_path(px, py, pz, is_closed, skip)
  local widx = find_anchors(x, y, z, delta, is_closed, skip, wforced)
  if not forced and not anchors_matter(widx, #W, is_closed) then return nil end
  local wu = anchored_params(x, y, z, widx, s.param, is_closed)
  if not wu then return nil end
  local idx = {}
  for r, k in ipairs(widx) do idx[r] = (k - 1) * st + 1 end
  ctx.anchors = idx
  if not sub then return bs.vector.new(wu) end
  -- every point of P from the subsample's parameters, by index in between
  local m, nw, u = #P, #W, {}
  for k = 1, nw do
    local i0, u0 = (k - 1) * st + 1, wu[k]
    local i1, u1 = k < nw and k * st + 1 or (is_closed and m + 1 or m), k < nw and wu[k + 1] or (is_closed and 1 or 1)
    u[i0] = u0
    for i = i0 + 1, math.min(i1 - 1, m) do u[i] = u0 + (u1 - u0) * (i - i0) / (i1 - i0) end
  end
  if is_closed then
    local below1 = 1 - 2 ^ -52
    for i = 1, m do if u[i] >= 1 then u[i] = below1 end end
  end
  return bs.vector.new(u)
end

-- The knots' parameters and corner positions in anchor space (ctx.knot_params,
-- ctx.knot_breaks), once the parameters are final: the averaging rule then spreads
-- knots over the anchors, not over the crowded samples.
function knots_on_anchors(ctx, positions)
  local idx = ctx.anchors
  if not idx then ctx.knot_params, ctx.knot_breaks = nil, nil; return end
  local u = ctx.params:totable()
  local ka = {}
  for r, i in ipairs(idx) do ka[r] = u[i] end
  ctx.knot_params = bs.vector.new(ka)
  if positions and #positions > 0 then
    local m, kb, r = #u, {}, 1
    for c, pos in ipairs(positions) do
      local j = math.floor(pos)
      local f = pos - j
      local uj, uk = u[j], (j < m and u[j + 1] or 1)
      local uc = uj + f * (uk - uj)
      while r < #idx and idx[r + 1] <= j do r = r + 1 end
      local a, b = ka[r], (r < #idx and ka[r + 1] or 1)
      kb[c] = r + (b > a and math.min(math.max((uc - a) / (b - a), 0), 1 - 1e-6) or 0)
      -- two corners within one gap of anchors (closer than 4 sigma) keep their order
      if c > 1 and kb[c] <= kb[c - 1] then kb[c] = kb[c - 1] + 1e-9 end
    end
    ctx.knot_breaks = kb
  end
end

-- }======================================================================

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
  local u = anchor_params(P, ctx)
  if u then return u end
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
  if not closed(ctx) or #P < 12 then knots_on_anchors(ctx); return {} end
  local o = { closed = true }
  if ctx.sigma > 0 then o.sigma = ctx.sigma end
  local sub = subsample(ctx, P)
  local idx, turns, where, at = bs.geom.corners(sub and sub.P or P, o)
  common.ok("corners", idx, turns, where)
  if #idx == 0 then knots_on_anchors(ctx); return {} end
  local m = #P
  local tt = turns:totable()
  if sub then
    -- found on the subsample: at its points (the chords across are negligible there)
    local full, forced, order = {}, {}, {}
    for i, k in ipairs(idx) do full[i] = (k - 1) * sub.stride + 1; forced[full[i]] = true; order[i] = i end
    table.sort(order, function(a, b) return full[a] < full[b] end)
    ctx.corner_turns = {}
    for i, k in ipairs(order) do ctx.corner_turns[i] = tt[k] end
    table.sort(full)
    ctx.corner_positions = full
    if ctx.anchors then ctx.params = anchor_params(P, ctx, forced) or ctx.params end
    knots_on_anchors(ctx, full)
    return full
  end
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
      if d2 >= (ANCHOR * ctx.sigma) ^ 2 then
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
    ctx.params = anchor_params(P, ctx, forced) or ctx.params
  end
  if #fpos > 0 then
    ctx.params = common.ok("corner parameters", bs.params_through_corners(P, ctx.params,
      bs.vector.new(fpos), bs.points.new(fpts), ctx.settings.param, { closed = true }))
  end
  knots_on_anchors(ctx, spos)
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
  local tries, best, chosen, stalls, prev = {}, nil, nil, 0, nil
  while true do
    local C, u, d, N, wm, mfit = fit_corrected(ctx, P, n, ctx.sub and 0 or 1, ctx.sub ~= nil)
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
  return common.add_trusted(ctx, { residuals = d:totable(), rms = d:rms(), max = max or 0,
                                   max_index = imax or 1 })
end

-- }======================================================================

function M.run(P, opts) return common.run(M, common.drop_closing_point(P, opts)) end

-- The report: the common fields plus what this strategy chose.
function M.report(ctx)
  local rep = common.report(ctx)
  rep.sigma = ctx.sigma
  rep.corners = ctx.corners
  rep.tries = ctx.tries
  return rep
end

return M
