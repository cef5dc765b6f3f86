-- lua/bsfit/strategy/anchors.lua
-- Anchors: parameters that samples closer than the noise cannot stretch (the `auto`
-- strategy's params and corners steps). Where samples crowd closer than the noise
-- (clusters, a densely sampled trailing edge), chords measure the noise, not the
-- contour: the parameters then run along "anchors" at least ANCHOR sigma apart (on the
-- path smoothed over 5 samples), the samples between two anchors placed by their
-- projection on the anchors' chord, and the knots are placed on the anchors, so a cluster
-- gets neither parameter length nor knots of its own (it would loop).
--
--   local anchors = require "bsfit.strategy.anchors"
--   local u = anchors.params(P, ctx, forced, sub)   -- Vector or nil (they do not matter)
--   anchors.knots(ctx, positions)                    -- ctx.knot_params, ctx.knot_breaks
--
-- ctx is the auto strategy's context: sigma, settings (param, trust), params, anchors;
-- sub its subsample of a large section ({P =, stride =}) or nil.

local bs = require "bsfit"
local common = require "bsfit.strategy.common"

local M = {}

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
function M.params(P, ctx, forced, sub)
  local s = ctx.settings
  if not (ctx.sigma and ctx.sigma > 0) or s.param == "uniform" or #P < 12 then return nil end
  local delta, is_closed = ANCHOR * ctx.sigma, common.closed(ctx)
  local trusted = common.trusted(ctx)
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
  -- an open section's last point ends its parameters (the subsample's last may fall short)
  if not is_closed then u[m] = 1 end
  if is_closed then
    local below1 = 1 - 2 ^ -52
    for i = 1, m do if u[i] >= 1 then u[i] = below1 end end
  end
  return bs.vector.new(u)
end

-- The knots' parameters and corner positions in anchor space (ctx.knot_params,
-- ctx.knot_breaks), once the parameters are final: the averaging rule then spreads
-- knots over the anchors, not over the crowded samples.
function M.knots(ctx, positions)
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

M.ANCHOR = ANCHOR

return M
