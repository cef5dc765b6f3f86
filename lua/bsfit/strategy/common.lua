-- lua/bsfit/strategy/common.lua
-- What the fitting strategies share: the step runner (option checking, per-step
-- timing, the `opts[step]` override rule), the steps both strategies use
-- (chord parameters, weights, the paper's control-point count), the deviation
-- measure and the report.
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

-- os is absent in a sandboxed engine: timing then reads 0.
local clock = (os and os.clock) or function() return 0 end
M.clock = clock

-- {======================================================================
-- Small numeric helpers
-- =======================================================================

-- Mean and population standard deviation of a Lua array (SPEC 2.5, 2.6).
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

-- Returns v, or raises "<what> failed: msg (CODE)" when v is the fail triple of
-- a numerical outcome (STYLE R3).
function M.ok(what, v, msg, code)
  if not v then
    error(("%s failed: %s%s"):format(what, tostring(msg), code and (" (" .. code .. ")") or ""), 0)
  end
  return v, msg
end

-- Point i of P as an array.
function M.point(P, i) return { P:get(i) } end

-- The weights vector w rotated like P:rotate(k): element k becomes the first.
function M.rotate_vector(w, k)
  local t, n, r = w:totable(), #w, {}
  for i = 1, n do r[i] = t[(i + k - 2) % n + 1] end
  return bs.vector.new(r)
end

-- }======================================================================

-- {======================================================================
-- Shared steps
-- =======================================================================

-- Whether the strategy fits a closed curve (setting `closed`, default true).
function M.closed(ctx) return ctx.settings.closed ~= false end

-- Chord-length parameters (SPEC 2.1); closed data includes the closing chord.
-- closed: true / false, or nil to follow the `closed` setting.
function M.params_chord(closed)
  return function(P, ctx)
    local c = closed
    if c == nil then c = M.closed(ctx) end
    return bs.params(P, ctx.settings.param, { closed = c })
  end
end

-- Weights from circumradius (SPEC 2.5, computed in C), times the per-point
-- weights read from the file (ctx.settings.point_weights) when there are any.
function M.weights_circumradius(P, ctx)
  local w = bs.weights.circumradius(P, { closed = M.closed(ctx) })
  return M.scale_weights(w, ctx.settings.point_weights)
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

-- Control-point count (SPEC 2.7): the number of curvature inversions of the
-- closed polygon; below 50% of the points, 50% of the points. Kept within what a
-- fit of degree p to m points can have: p+1 .. m.
function M.count_inversions(P, ctx)
  local m, p = #P, ctx.settings.degree
  local inv = bs.geom.inflections(P, { closed = M.closed(ctx) })
  ctx.inflections = inv
  local n = inv
  if inv < 0.5 * m then n = m // 2 end
  return M.clamp_count(n, m, p)
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

-- Closest-point distances from the points of P to curve C: a Lua array, the RMS,
-- the maximum and its (1-based) index. This is the measure every strategy reports,
-- so that their numbers compare (a fit's own residuals are measured at the
-- parameters ū_k, which the paper's closing step changes). One C call: the curve is
-- sampled once, each point bracketed by its nearest sample and refined by Newton.
function M.deviations(C, P)
  local _, dv = C:closest_many(P)
  local d = dv:totable()
  local m, sum, max, imax = #P, 0, -1, 1
  for i = 1, m do
    sum = sum + d[i] * d[i]
    if d[i] > max then max, imax = d[i], i end
  end
  return d, math.sqrt(sum / m), max, imax
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
function M.run(strategy, P, opts)
  P = check_points(P)
  opts = check_options(strategy, opts)
  if #P < 3 then
    error(("%s: %d points, at least 3 needed for a closed section"):format(strategy.name, #P), 0)
  end
  local ctx = { strategy = strategy, opts = opts, settings = settings_of(strategy, opts),
                P = P, times = {}, cache = {} }
  local t0 = clock()
  for _, name in ipairs(strategy.order) do
    local v = M.call(ctx, name, ctx.P)
    ctx[name] = v
    if M.is_curve(v) then ctx.curve = v end
  end
  if opts.smooth ~= nil then
    local t1 = clock()
    ctx.smoothing = M.smooth_curve(ctx, opts.smooth)
    ctx.times.smooth = (clock() - t1) * 1000
    if strategy.steps.measure then ctx.measure = M.call(ctx, "measure", ctx.P) end
  end
  ctx.total_ms = (clock() - t0) * 1000
  return ctx.curve, (strategy.report or M.report)(ctx)
end

-- The smoothing step every strategy accepts (SPEC 3): opts.smooth = k (or {k = k}) box
-- filters the fitted curve over k knot spans (the moving average of k control points
-- on uniform knots; the exact filter of the same width, k times the mean span, on any
-- other knots), {delta = d} over [t - d, t + d]. The curve becomes one degree higher.
-- Returns what it changed: the maximum deviation it introduced, and the total turning
-- and bending energy before and after.
function M.smooth_curve(ctx, spec)
  local C = ctx.curve
  if math.type(spec) == "integer" then spec = { k = spec } end
  if type(spec) ~= "table" or (spec.delta == nil and (math.type(spec.k) ~= "integer" or spec.k < 1)) then
    error("bad argument #2 to 'run' (option 'smooth' must be an integer k >= 1, {k = k} or {delta = d})", 0)
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
  return rep
end

-- The measure step: deviations of the original points from ctx.curve.
function M.measure(P, ctx)
  local d, rms, max, imax = M.deviations(ctx.curve, P)
  return { residuals = d, rms = rms, max = max, max_index = imax }
end

-- }======================================================================

return M
