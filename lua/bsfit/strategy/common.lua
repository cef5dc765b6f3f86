-- lua/bsfit/strategy/common.lua
-- What the fitting strategies share: the step runner (option checking, per-step
-- timing, the `opts[step]` override rule), the steps both strategies use
-- (chord parameters, weights, the paper's control-point count), the trusted points
-- of a file's point weights (and the parameters and weights that follow them), the
-- deviation measure and the report.
--
-- A strategy is a table
--   { name = "...", order = {"params", "weights", ...}, steps = {params = f, ...},
--     settings = {degree = 3, ...} }
-- and `common.run(strategy, P, opts)` runs its steps in order. Each step is
-- `f(P, ctx) -> value`; the value is stored as ctx[step]. `opts[step]` replaces a
-- step: a function is called in its place, any other value is taken as the step's
-- result (`{count = 24}`, `{weights = vector}`). `opts[setting]` overrides a
-- setting. Any other option name raises.

local bs = require "bsfit"

local M = {}

-- The step timer: the monotonic wall clock of bs.parallel (cheap, and per run even
-- when `reconstruct -j N` runs sections on several threads, where os.clock would
-- count every thread's CPU time); os.clock without it; 0 when neither is there.
local clock = (bs.parallel and bs.parallel.clock) or (os and os.clock) or function() return 0 end
M.clock = clock

-- {======================================================================
-- Small numeric helpers
-- =======================================================================

-- Mean and population standard deviation of a Lua array (docs/method.md §7, §8).
function M.mean_std(t)
  local n, s, s2 = #t, 0, 0
  if n == 0 then return 0, 0 end
  for i = 1, n do s = s + t[i] end
  local mean = s / n
  for i = 1, n do local d = t[i] - mean; s2 = s2 + d * d end
  return mean, math.sqrt(s2 / n)
end

-- Distance of point x (array) from the line through o with direction d, and the
-- foot of the perpendicular. Any dimension.
function M.line_foot(x, o, d)
  local dd, t = 0, 0
  for k = 1, #o do dd = dd + d[k] * d[k]; t = t + (x[k] - o[k]) * d[k] end
  if dd == 0 then error("tangent direction is zero (coincident points)", 2) end
  t = t / dd
  local foot, dist2 = {}, 0
  for k = 1, #o do
    foot[k] = o[k] + t * d[k]
    local e = x[k] - foot[k]
    dist2 = dist2 + e * e
  end
  return math.sqrt(dist2), foot
end

-- What the fitter said about each curve it made (rcond, solver), for the report: keyed
-- weakly by the curve; `last_fit` is the latest fit's, for curves no fit made directly.
local fit_info = setmetatable({}, { __mode = "k" })
local last_fit

-- Returns v, or raises "<what> failed: msg (CODE)" when v is the fail triple of
-- a numerical outcome (STYLE R3). When v is a fitter's curve and msg its report, keeps
-- the report's rcond and solver for M.report.
function M.ok(what, v, msg, code)
  if not v then
    error(("%s failed: %s%s"):format(what, tostring(msg), code and (" (" .. code .. ")") or ""), 0)
  end
  if type(msg) == "table" and msg.rcond ~= nil and M.is_curve(v) then
    last_fit = { rcond = msg.rcond, solver = msg.solver }
    fit_info[v] = last_fit
  end
  return v, msg
end

-- Point i of P as an array.
function M.point(P, i) return { P:get(i) } end

-- The weights vector w (Vector or table) rotated like P:rotate(k): element k becomes
-- the first. A new Vector, made from two slices of w's bytes (no per-element Lua work).
function M.rotate_vector(w, k)
  if type(w) == "table" then w = bs.vector.new(w) end
  local s, o = w:bytes(), 8 * (k - 1)
  return bs.vector.frombytes(s:sub(o + 1) .. s:sub(1, o))
end

-- Closed parameters u (Vector or table, one period [0, 1)) of points rotated like
-- P:rotate(k): shifted so that point k's is 0, as a new Vector.
function M.rotate_params(u, k)
  local t = type(u) == "table" and u or u:totable()
  local m, r = #t, {}
  local u0, below1 = t[k], 1 - 2 ^ -53
  for i = 1, m do
    local v = t[(i + k - 2) % m + 1] - u0
    if v < 0 then v = v + 1 end
    r[i] = v < 1 and v or below1 -- a zero closing chord would give exactly 1
  end
  return bs.vector.new(r)
end

-- }======================================================================

-- {======================================================================
-- Shared steps
-- =======================================================================

-- Whether the strategy fits a closed curve (setting `closed`, default true).
function M.closed(ctx) return ctx.settings.closed ~= false end

-- The per-point weights of the file (setting point_weights, a Vector or table), checked
-- against the m points; nil without them.
local function point_weights(pw, m)
  if pw == nil then return nil end
  local mt = getmetatable(pw)
  if type(pw) ~= "table" and not (type(mt) == "table" and mt.__name == "bsfit.Vector") then
    error("bad argument #2 to 'run' (option 'point_weights' must be a bsfit.Vector or table)", 0)
  end
  if #pw ~= m then error(("point_weights has %d values for %d points"):format(#pw, m), 0) end
  if type(pw) == "table" then
    for i = 1, m do
      if type(pw[i]) ~= "number" then
        error(("point_weights: value %d is %s (must be positive and finite)"):format(i, tostring(pw[i])), 0)
      end
    end
  end
  return pw
end

-- The setting trust (default 0.1), checked.
local function trust_of(ctx)
  local trust = ctx.settings.trust or 0.1
  if type(trust) ~= "number" or not (trust >= 0 and trust < 1) then
    error("bad argument #2 to 'run' (option 'trust' must be a number in [0, 1))", 0)
  end
  return trust
end

-- The trusted points (the rule of bs.params_trusted, bs.weights.untrusted in C): weight at
-- least `trust` (setting, default 0.1) times the median of the point_weights. Returns nil
-- when every point is trusted (no point_weights, equal weights, trust 0), else a table
--   { out = {untrusted indices, increasing}, isout = {[i] = true}, n = #trusted,
--     points = Points of the trusted ones (nil when fewer than 3) }
-- P: the run's points (default ctx.P). Computed once per run (kept in ctx.cache when
-- there is one). What follows from it works on the few untrusted points and the runs of
-- trusted ones.
function M.trusted(ctx, P)
  if ctx.settings.point_weights == nil then return nil end
  local cache = ctx.cache or {}
  local c = cache.trusted
  if c ~= nil then return c or nil end
  P = P or ctx.P
  local trust = trust_of(ctx)
  local w = point_weights(ctx.settings.point_weights, #P)
  local out, msg = bs.weights.untrusted(w, trust)
  if not out then error("point_weights: " .. msg:gsub("^weight", "value"), 0) end
  c = false
  if #out > 0 then
    local isout = {}
    for _, i in ipairs(out) do isout[i] = true end
    c = { out = out, isout = isout, n = #P - #out }
    if c.n >= 3 then c.points = M.subset_runs(P, out) end
  end
  cache.trusted = c
  return c or nil
end

-- The runs of indices 1..m that avoid the increasing indices `out`: an array of
-- {first, last} pairs (in order, empty runs left out).
local function runs(out, m)
  local r, a = {}, 1
  for j = 1, #out + 1 do
    local b = (out[j] or m + 1) - 1
    if b >= a then r[#r + 1] = { a, b } end
    a = b + 2
  end
  return r
end

-- The points of P not in the increasing indices `out`, as a new Points (one byte
-- slice per run of kept points).
function M.subset_runs(P, out)
  local s, dim = P:bytes(), P:dim()
  local size, parts = 8 * dim, {}
  for _, r in ipairs(runs(out, #P)) do parts[#parts + 1] = s:sub((r[1] - 1) * size + 1, r[2] * size) end
  return bs.points.frombytes(table.concat(parts), dim)
end

-- The 1-based index in the full data of the j-th trusted point.
function M.trusted_index(t, j)
  local i = j
  for _, o in ipairs(t.out) do
    if o <= i then i = i + 1 else break end
  end
  return i
end

-- The maximum of Vector d (values in the order of the points rotated so that point
-- k is first) over the trusted points of t.
function M.trusted_max(d, t, k)
  local m = #d
  d = d:copy()
  for _, i in ipairs(t.out) do d:set((i - k) % m + 1, 0) end
  return (d:max())
end

-- Chord-length parameters (docs/method.md §2); closed data includes the closing chord.
-- closed: true / false, or nil to follow the `closed` setting.
function M.params_chord(closed)
  return function(P, ctx)
    local c = closed
    if c == nil then c = M.closed(ctx) end
    return M.ok("params", bs.params(P, ctx.settings.param, { closed = c }))
  end
end

-- Chord parameters (docs/method.md §2) that down-weighted points cannot stretch: with
-- point_weights, computed over the trusted points only and interpolated for the
-- others (bs.params_trusted, the rule of M.trusted); without, plain bs.params.
-- closed: true / false, or nil to follow the `closed` setting.
function M.params_trusted(closed)
  return function(P, ctx)
    local c, s = closed, ctx.settings
    if c == nil then c = M.closed(ctx) end
    if s.point_weights == nil then return M.ok("params", bs.params(P, s.param, { closed = c })) end
    point_weights(s.point_weights, #P) -- the strategies' messages for misuse
    return M.ok("params", bs.params_trusted(P, s.param, { closed = c, weights = s.point_weights,
                                                         trust = trust_of(ctx) }))
  end
end

-- Weights from circumradius (docs/method.md §7, computed in C), times the per-point
-- weights read from the file (ctx.settings.point_weights) when there are any.
function M.weights_circumradius(P, ctx)
  local w = bs.weights.circumradius(P, { closed = M.closed(ctx) })
  return M.scale_weights(w, ctx.settings.point_weights)
end

-- The same rule read off the shape the trusted points describe (M.trusted): the
-- circles pass through trusted neighbours only, so an outlier neither looks like a
-- tight corner nor makes its neighbours look like one (both would pull the curve
-- towards it); an untrusted point gets the weight interpolated, by index, between its
-- trusted neighbours (open data: the nearest one at the ends). Then times the
-- point_weights. Without untrusted points this is M.weights_circumradius. The
-- trusted points' weights are copied as byte runs: Lua touches only the others.
function M.weights_circumradius_trusted(P, ctx)
  local t = M.trusted(ctx, P)
  if t == nil or t.points == nil then return M.weights_circumradius(P, ctx) end
  local closed, m, out, nt = M.closed(ctx), #P, t.out, t.n
  local wt = bs.weights.circumradius(t.points, { closed = closed })
  local s, parts = wt:bytes(), {}
  local k, i = 1, 1 -- out[k]: the next untrusted index; i: the next index to write
  while i <= m do
    local a = out[k]
    if a == nil or a > i then -- trusted i..e: subset positions i-k+1 .. e-k+1
      local e = (a or m + 1) - 1
      parts[#parts + 1] = s:sub(8 * (i - k) + 1, 8 * (e - k + 1))
      i = e + 1
    else -- untrusted a..b, between trusted L and R (cyclically when closed)
      local k0, b = k, a
      while out[k + 1] == b + 1 do k = k + 1; b = b + 1 end
      local L, R, vL, vR
      if a > 1 then L, vL = a - 1, wt:get(a - k0)
      elseif closed then L, vL = M.trusted_index(t, nt) - m, wt:get(nt) end
      if b < m then R, vR = b + 1, wt:get(b + 1 - k)
      elseif closed then R, vR = M.trusted_index(t, 1) + m, wt:get(1) end
      L, vL = L or R, vL or vR
      R, vR = R or L, vR or vL
      for x = a, b do
        local f = R > L and (x - L) / (R - L) or 0
        parts[#parts + 1] = string.pack("d", vL + (vR - vL) * f)
      end
      i, k = b + 1, k + 1
    end
  end
  return M.scale_weights(bs.vector.frombytes(table.concat(parts)), ctx.settings.point_weights)
end

-- w times the optional per-point weights pw (Vector or table), as a new Vector.
function M.scale_weights(w, pw)
  if pw == nil then return w end
  local a, b = w:totable(), type(pw) == "table" and pw or pw:totable()
  if #b ~= #a then
    error(("point_weights has %d values for %d points"):format(#b, #a), 0)
  end
  for i = 1, #a do a[i] = a[i] * b[i] end
  return bs.vector.new(a)
end

-- Number of distinct values among sorted parameters (a Vector or a table): points
-- that coincide share a parameter (bs.params), and a fit cannot have more control
-- points than distinct parameters.
function M.distinct_params(u)
  if type(u) ~= "table" then return u:distinct() end
  local n, last = 0, nil
  for i = 1, #u do
    if u[i] ~= last then n, last = n + 1, u[i] end
  end
  return n
end

-- Control-point count (docs/method.md §9-10): the number of curvature inversions of the
-- closed polygon; below 50% of the points, 50% of the points. Kept within what a
-- fit of degree p to m points can have: p+1 .. the number of distinct parameters
-- (repeated points would otherwise leave knot spans without data).
function M.count_inversions(P, ctx)
  local m, p = #P, ctx.settings.degree
  local inv = bs.geom.inflections(P, { closed = M.closed(ctx) })
  ctx.inflections = inv
  local n = inv
  if inv < 0.5 * m then n = m // 2 end
  local distinct = ctx.params and M.distinct_params(ctx.params) or m
  if distinct < p + 1 then
    error(("%s: %d distinct points are too few for a curve of degree %d (at least %d needed)")
          :format(ctx.strategy.name, distinct, p, p + 1), 0)
  end
  return M.clamp_count(n, math.min(m, distinct), p)
end

function M.clamp_count(n, m, p)
  if n < p + 1 then n = p + 1 end
  if n > m then n = m end
  return n
end

-- }======================================================================

-- {======================================================================
-- Deviations: distance of every point from the final curve
-- =======================================================================

-- The measure of the distances dv (a Vector, one per point of the run) that every strategy
-- reports: { residuals = a Lua array, rms, max, max_index (1-based) }, and over the
-- trusted points only when some are not (M.trusted: max_trusted, max_trusted_index,
-- rms_trusted, what the fit was asked to follow). The sums and the first maximum are
-- taken in C; the untrusted few are zeroed in a copy, so no loop over every point runs
-- in Lua.
function M.measure_of(ctx, dv)
  local max, imax = dv:max()
  local r = { residuals = dv:totable(), rms = dv:rms() or 0, max = max or 0, max_index = imax or 1 }
  local t = M.trusted(ctx)
  if t == nil then return r end
  local z = dv:copy()
  for _, i in ipairs(t.out) do z:set(i, 0) end
  local tmax, ti = z:max()
  if not (tmax and tmax > 0) then -- every trusted residual zero: the first trusted point's
    tmax, ti = 0, 1
    while t.isout[ti] do ti = ti + 1 end
  end
  r.max_trusted, r.max_trusted_index = tmax, ti
  r.rms_trusted = (z:rms() or 0) * math.sqrt(#z / t.n)
  return r
end

-- }======================================================================

-- {======================================================================
-- What scanners write: a repeated closing point, repeated consecutive points
-- =======================================================================

local function same_point(P, i, j)
  local a, b = { P:get(i) }, { P:get(j) }
  for k = 1, #a do
    if a[k] ~= b[k] then return false end
  end
  return true
end

-- Whether every point of P is the first.
function M.all_same(P)
  for i = 2, #P do
    if not same_point(P, 1, i) then return false end
  end
  return true
end

-- The first n values of point weights pw (Vector or table) as a table.
local function head_of(pw, n)
  local t = type(pw) == "table" and pw or pw:totable()
  local r = {}
  for i = 1, math.min(n, #t) do r[i] = t[i] end
  return r
end

-- Called by every strategy's run before anything else: a closed section whose last
-- point repeats the first (scanners close their loops that way) loses that point,
-- and the point_weights their last value. Returns P (a Points), the options (a copy
-- when changed) and the notes common.run adds to the report: warnings (strings) and
-- dropped_closing_point. Open fits (closed = false) keep every point.
function M.drop_closing_point(P, opts)
  if type(P) == "table" then P = bs.points.new(P) end
  local notes = { warnings = {} }
  local closed = not (type(opts) == "table" and opts.closed == false)
  local ok, m = pcall(function() return #P end)
  if not closed or not ok or math.type(m) ~= "integer" or m < 3 or not same_point(P, 1, m)
     or same_point(P, 1, 2) and same_point(P, 1, m // 2) and M.all_same(P) then
    return P, opts, notes -- all points coinciding is another failure, said as such later
  end
  -- the closing point may be given more than once (a scanner that repeats its last
  -- sample): every repeat of point 1 at the end goes
  local keep = m - 1
  while keep > 2 and same_point(P, 1, keep) do keep = keep - 1 end
  local o = {}
  for k, v in pairs(opts or {}) do o[k] = v end
  local pw = o.point_weights
  if pw ~= nil and (type(pw) == "table" or getmetatable(pw)) then
    o.point_weights = head_of(pw, keep)
  end
  notes.dropped_closing_point = true
  notes.warnings[1] = keep == m - 1
    and ("point %d repeats point 1 (a closed section's closing point): dropped"):format(m)
    or ("points %d to %d repeat point 1 (a closed section's closing point): dropped")
      :format(keep + 1, m)
  return P:slice(1, keep), o, notes
end

-- Merges runs of repeated consecutive points (after M.drop_closing_point) into one
-- point whose weight is the run's (the sum of its point_weights, or its length): the
-- same weighted least-squares problem without coincident points, which the paper's
-- rules (circumradius, averaging knots) cannot take. Returns P, opts and map (map[j] = index in the input of merged point j), or
-- P, opts, nil when nothing repeats. Adds a warning to notes.
function M.merge_repeats(P, opts, notes)
  local okm, m = pcall(function() return #P end)
  if not okm or math.type(m) ~= "integer" then return P, opts, nil end -- misuse: run says
  local keep, map, runs = {}, {}, 0
  for i = 1, m do
    if i > 1 and same_point(P, i, map[#map]) then
      runs = runs + 1
    else
      map[#map + 1] = i
    end
    keep[i] = #map
  end
  if runs == 0 or #map == 1 then return P, opts, nil end -- all coinciding: said later
  local pw = opts and opts.point_weights
  pw = pw and (type(pw) == "table" and pw or pw:totable())
  local w, parts, s, size = {}, {}, P:bytes(), 8 * P:dim()
  for i = 1, m do
    w[keep[i]] = (w[keep[i]] or 0) + (pw and pw[i] or 1)
  end
  for j, i in ipairs(map) do parts[j] = s:sub((i - 1) * size + 1, i * size) end
  local o = {}
  for k, v in pairs(opts or {}) do o[k] = v end
  o.point_weights = w
  notes.warnings[#notes.warnings + 1] =
    ("%d repeated consecutive points merged into their first (weights added)"):format(runs)
  return bs.points.frombytes(table.concat(parts), P:dim()), o, map
end

-- The report of a fit to merged points (M.merge_repeats) in the input's terms:
-- indices mapped back, residuals and weights repeated for the merged points (a
-- repeated point is where its first is: the same distance).
function M.unmerge_report(rep, map, m)
  local back = {}
  for j, i in ipairs(map) do back[i] = j end
  local function expand(v)
    if v == nil then return nil end
    local t, r, j = type(v) == "table" and v or v:totable(), {}, 0
    for i = 1, m do
      if back[i] then j = back[i] end
      r[i] = t[j]
    end
    return type(v) == "table" and r or bs.vector.new(r)
  end
  rep.residuals, rep.weights = expand(rep.residuals), expand(rep.weights)
  for _, k in ipairs { "start_index", "max_index", "max_trusted_index" } do
    if rep[k] then rep[k] = map[rep[k]] end
  end
  if rep.candidates then
    for i, k in ipairs(rep.candidates) do rep.candidates[i] = map[k] end
  end
  rep.points = m
  return rep
end

-- }======================================================================

-- {======================================================================
-- The runner
-- =======================================================================

local function check_points(P)
  if type(P) == "table" then P = bs.points.new(P) end
  if type(P) ~= "userdata" or not pcall(P.dim, P) then
    error("bad argument #1 to 'run' (bsfit.Points expected)", 3)
  end
  return P
end

-- Raises for option names that are neither a step nor a setting.
local function check_options(strategy, opts)
  if opts == nil then return {} end
  if type(opts) ~= "table" then
    error("bad argument #2 to 'run' (table of options expected, got " .. type(opts) .. ")", 3)
  end
  for k in pairs(opts) do
    if type(k) ~= "string" or (strategy.steps[k] == nil and strategy.settings[k] == nil
                               and not (strategy.optional or {})[k] and k ~= "smooth") then
      local names = {}
      for _, s in ipairs(strategy.order) do names[#names + 1] = s end
      for s in pairs(strategy.settings) do names[#names + 1] = s end
      for s in pairs(strategy.optional or {}) do names[#names + 1] = s end
      names[#names + 1] = "smooth"
      table.sort(names)
      error(("bad argument #2 to 'run' (unknown option '%s'; %s accepts: %s)")
            :format(tostring(k), strategy.name, table.concat(names, ", ")), 3)
    end
  end
  return opts
end

-- Settings: the strategy's defaults, overridden by opts.
local function settings_of(strategy, opts)
  local s = {}
  for k, v in pairs(strategy.settings) do s[k] = v end
  for k in pairs(strategy.optional or {}) do s[k] = nil end
  for k, v in pairs(opts) do
    if strategy.steps[k] == nil then s[k] = v end
  end
  if math.type(s.degree) ~= "integer" or s.degree < 1 then
    error("bad argument #2 to 'run' (option 'degree' must be an integer >= 1)", 4)
  end
  return s
end

-- The function that performs step `name`: the override from opts, or the default.
function M.step(ctx, name)
  local o = ctx.opts[name]
  if o == nil then return ctx.strategy.steps[name] end
  if type(o) == "function" then return o end
  local mt = getmetatable(o)
  if type(o) == "table" and type(mt) == "table" and mt.__call then return o end
  return function() return o end
end

-- Runs step `name` on points Q, timing it (times add up over repeated calls).
function M.call(ctx, name, Q)
  local t0 = clock()
  local v = M.step(ctx, name)(Q, ctx)
  ctx.times[name] = (ctx.times[name] or 0) + (clock() - t0) * 1000
  if v == nil then
    error(("%s: step '%s' returned nothing"):format(ctx.strategy.name, name), 0)
  end
  return v
end

-- True when v is a bsfit.Curve.
function M.is_curve(v)
  local mt = getmetatable(v)
  return type(mt) == "table" and mt.__name == "bsfit.Curve"
end

-- Runs every step of `strategy` in order on P. The curve is the last curve a step
-- returned (ctx.curve). Returns the curve and the report. Raises on misuse and on
-- a failed step (message "<strategy>: ...").
-- {======================================================================
-- Explicit requests the data cannot honour: an error or a warning, never silence
-- =======================================================================

-- Number of distinct points of P (consecutive repeats and a closing repeat aside,
-- points that coincide share a parameter and cannot carry a control point each).
local function distinct_points(P)
  local seen, n = {}, 0
  for i = 1, #P do
    local key = string.pack(("d"):rep(P:dim()), P:get(i))
    if not seen[key] then seen[key], n = true, n + 1 end
  end
  return n
end

-- An explicit count (opts.count, a plain integer) must be one a fit can have: at least
-- degree + 1, at most the number of distinct points. Raises naming the limit.
function M.check_count(strategy, P, opts, settings)
  local n = opts.count
  if n == nil or type(n) == "function" or (getmetatable(n) or {}).__call then return end
  local p = settings.degree
  if math.type(n) ~= "integer" then
    error(("%s: count must be an integer, got %s"):format(strategy.name, tostring(n)), 0)
  end
  if n < p + 1 then
    error(("%s: count %d is below the minimum for degree %d (at least %d)")
          :format(strategy.name, n, p, p + 1), 0)
  end
  if n > #P then
    error(("%s: count %d is more than the %d points allow (at most %d)")
          :format(strategy.name, n, #P, #P), 0)
  end
  -- counting distinct points costs a Lua pass over P: only where it can matter (a count
  -- near the point count) and affordable; check_count_honoured catches the rest
  local d = (n > #P // 2 and #P <= 200000) and distinct_points(P) or n
  if n > d then
    error(("%s: count %d is more than the %d distinct points allow (at most %d)")
          :format(strategy.name, n, d, d), 0)
  end
end

-- After the steps: a strategy that fitted fewer control points than an explicit
-- count asked for (its knot placement keeps data in every span) must say so.
function M.check_count_honoured(strategy, opts, C)
  local n = opts.count
  if math.type(n) ~= "integer" or not M.is_curve(C) then return end
  local got = C:distinct()
  if got ~= n then
    error(("%s: count %d cannot be honoured on these points: at most %d control points here")
          :format(strategy.name, n, got), 0)
  end
end

-- tol (a setting of auto and periodic) not met: the best fit, with a warning. The
-- distance judged is the one the strategy reports (max_trusted when the file
-- down-weights points).
function M.check_tol(settings, rep)
  local tol = settings.tol
  if type(tol) ~= "number" then return end
  local got = rep.max_trusted or rep.max
  if type(got) == "number" and got > tol then
    rep.warnings[#rep.warnings + 1] = ("tol %g not met: max deviation %.3g with %s control points")
      :format(tol, got, tostring(rep.count))
    rep.tol_met = false
  else
    rep.tol_met = true
  end
end

-- }======================================================================

-- notes (optional): what M.drop_closing_point found, added to the report (warnings,
-- dropped_closing_point).
function M.run(strategy, P, opts, notes)
  P = check_points(P)
  opts = check_options(strategy, opts)
  local settings = settings_of(strategy, opts)
  local need = math.max(3, settings.degree + 1)
  if #P < need then
    error(("%s: %d point%s too few for a curve of degree %d (at least %d needed%s)")
          :format(strategy.name, #P, #P == 1 and " is" or "s are", settings.degree, need,
                  notes and notes.dropped_closing_point and "; the repeated closing point dropped"
                  or ""), 0)
  end
  if M.all_same(P) then
    error(("%s: all %d points coincide"):format(strategy.name, #P), 0)
  end
  M.check_count(strategy, P, opts, settings)
  local ctx = { strategy = strategy, opts = opts, settings = settings,
                P = P, times = {}, cache = {}, warnings = {} }
  last_fit = nil -- a fit of an earlier run says nothing of this one
  local t0 = clock()
  for _, name in ipairs(strategy.order) do
    local v = M.call(ctx, name, ctx.P)
    ctx[name] = v
    if M.is_curve(v) then ctx.curve = v end
  end
  M.check_count_honoured(strategy, opts, ctx.curve)
  ctx.fitted = ctx.curve
  if opts.smooth ~= nil then
    local t1 = clock()
    ctx.smoothing = M.smooth_curve(ctx, opts.smooth)
    ctx.times.smooth = (clock() - t1) * 1000
    if strategy.steps.measure then ctx.measure = M.call(ctx, "measure", ctx.P) end
  end
  ctx.total_ms = (clock() - t0) * 1000
  local rep = (strategy.report or M.report)(ctx)
  local warnings = {}
  for _, w in ipairs(notes and notes.warnings or {}) do warnings[#warnings + 1] = w end
  for _, w in ipairs(ctx.warnings or {}) do warnings[#warnings + 1] = w end
  rep.warnings = warnings
  rep.dropped_closing_point = notes and notes.dropped_closing_point or nil
  M.check_tol(settings, rep)
  return ctx.curve, rep
end

-- The tolerance form of the smoothing step (M.smooth_curve): checks spec, smooths C by
-- bs.filter.smooth; returns the curve and the report of M.smooth_curve with the order,
-- width, knots added and whether anything changed.
local function smooth_to_tol(C, spec)
  local bad = "bad argument #2 to 'run' (option 'smooth': %s)"
  local tol = spec.tol
  if type(tol) ~= "number" or not (tol > 0 and tol < math.huge) then
    error(bad:format("tol must be a number > 0"), 0)
  end
  for k in pairs(spec) do
    if k ~= "tol" and k ~= "order" and k ~= "degree" then
      error(bad:format("unknown field '" .. tostring(k) .. "' with tol"), 0)
    end
  end
  for _, k in ipairs { "order", "degree" } do
    local v = spec[k]
    if v ~= nil and (math.type(v) ~= "integer" or v < 1) then
      error(bad:format(k .. " must be an integer >= 1"), 0)
    end
  end
  local S, rep = M.ok("smoothing", bs.filter.smooth(C, { tol = tol, order = spec.order,
                                                         degree = spec.degree }))
  return S, { deviation = rep.max_deviation, turning = { rep.turning_before, rep.turning_after },
              bending = { rep.energy_before, rep.energy_after }, changed = rep.changed,
              order = rep.order, delta = rep.delta, knots_added = rep.knots_added,
              degree = S:degree() }
end

-- The smoothing step every strategy accepts (docs/filtering.md): opts.smooth = k (or {k = k}) box
-- filters the fitted curve over k knot spans (the moving average of k control points
-- on uniform knots; the exact filter of the same width, k times the mean span, on any
-- other knots), {delta = d} over [t - d, t + d]. The curve becomes one degree higher.
-- {tol = t [, order = r] [, degree = q]} smooths to a tolerance instead
-- (bs.filter.smooth, docs/filtering.md): the smoothest kernel filter whose result,
-- brought back to degree q (default 3), stays within t of the fit; the report then also
-- gives the order and width chosen, the knots added and whether anything changed.
-- Returns what it changed: the maximum deviation it introduced, and the total turning
-- and bending energy before and after.
function M.smooth_curve(ctx, spec)
  local C = ctx.curve
  if math.type(spec) == "integer" then spec = { k = spec } end
  if type(spec) == "table" and spec.tol ~= nil then
    local S, rep = smooth_to_tol(C, spec)
    ctx.curve = S
    return rep
  end
  if type(spec) ~= "table"
     or (spec.delta == nil and (math.type(spec.k) ~= "integer" or spec.k < 1)) then
    error("bad argument #2 to 'run' (option 'smooth' must be an integer k >= 1, {k = k}, "
          .. "{delta = d} or {tol = t})", 0)
  end
  local S
  if spec.delta ~= nil then
    S = M.ok("smoothing", bs.filter.box(C, { delta = spec.delta }))
  elseif C:is_uniform() then
    S = M.ok("smoothing", bs.filter.box(C, spec.k))
  else
    local a, b = C:domain()
    S = M.ok("smoothing", bs.filter.box(C, { delta = spec.k * (b - a) / C:distinct() / 2 }))
  end
  ctx.curve = S
  return { deviation = C:max_deviation(S), turning = { C:total_turning(), S:total_turning() },
           bending = { C:bending_energy(), S:bending_energy() } }
end

-- The report table (see the strategy modules for the fields).
function M.report(ctx)
  local rep = ctx.measure or {}
  rep.strategy = ctx.strategy.name
  rep.points = #ctx.P
  rep.weights = ctx.weights
  rep.count = ctx.count
  rep.inflections = ctx.inflections
  rep.start_index = ctx.start_index or 1
  rep.candidates = ctx.candidates or {}
  rep.candidate_dt = ctx.candidate_dt or {}
  rep.tries = ctx.tries
  rep.times = ctx.times
  rep.total_ms = ctx.total_ms
  rep.smoothing = ctx.smoothing
  -- the fit that made the curve (before smoothing), else the fit that the curve was
  -- built from (carvalho's closing), else the run's last fit (auto's assembled pieces)
  local f = fit_info[ctx.fitted or ctx.curve] or (M.is_curve(ctx.fit) and fit_info[ctx.fit])
            or last_fit
  if f then rep.rcond, rep.solver = f.rcond, f.solver end
  return rep
end

-- The measure step: closest-point distances from the original points to ctx.curve (the
-- measure every strategy reports, so that their numbers compare: a fit's own residuals
-- are measured at the parameters ū_k, which the paper's closing step changes). One C
-- call: the curve is sampled once, each point bracketed by its nearest sample and
-- refined by Newton.
function M.measure(P, ctx)
  local _, dv = ctx.curve:closest_many(P)
  return M.measure_of(ctx, dv)
end

-- }======================================================================


-- {======================================================================
-- Helpers of the strategies' steps
-- =======================================================================

-- v as a Lua array: a table as it is, a Vector's values, {} for nil.
function M.as_table(v)
  if v == nil then return {} end
  if type(v) == "table" then return v end
  return v:totable()
end

-- Adds a warning for rep.warnings.
function M.warn(ctx, msg)
  ctx.warnings = ctx.warnings or {}
  ctx.warnings[#ctx.warnings + 1] = msg
end

-- Large sections are read through a subsample of at most SUBSAMPLE points for the
-- noise level, the corners and the distances measured during the count search:
-- all three are local or statistical, and the fits themselves still use every point.
local SUBSAMPLE = 5000

-- every s-th point of P (s = ceil(#P / SUBSAMPLE)) from point `first` (1 when nil) round
-- to the one before it, or nil when P is not larger
function M.thinned(P, first)
  if #P <= SUBSAMPLE then return nil end
  local t, m, k = {}, #P, math.ceil(#P / SUBSAMPLE)
  first = first or 1
  for j = 0, m - 1, k do t[#t + 1] = { P:get((first - 1 + j) % m + 1) } end
  return bs.points.new(t)
end

-- The every-k-th subsample of a closed 2D section, from where the segmentation reads it
-- (bs.geom.segment_start), so what is read off it does not depend on the sample the data
-- start at; of any other, from its first point (M.thinned). nil when P is small.
function M.thinned_closed(P, closed)
  if #P <= SUBSAMPLE then return nil end
  return M.thinned(P, closed and P:dim() == 2 and bs.geom.segment_start(P) or 1)
end

-- ctx.sub = {P = Points, stride = s, u = its parameters (set later)} when #P > SUBSAMPLE
function M.subsample(ctx, P)
  if ctx.sub ~= nil or #P <= SUBSAMPLE then return ctx.sub end
  ctx.sub = { P = M.thinned(P), stride = math.ceil(#P / SUBSAMPLE) }
  return ctx.sub
end

-- every s-th value of a Vector, as a Vector
function M.every(v, s)
  local r = {} -- read only the values kept, not the whole section into a table
  for i = 1, #v, s do r[#r + 1] = v:get(i) end
  return bs.vector.new(r)
end


-- }======================================================================

return M
