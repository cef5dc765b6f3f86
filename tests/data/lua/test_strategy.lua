-- test_strategy.lua
-- A tiny fitting strategy for the engine tests (tests/c/test_engine.c and the
-- embedding example): the degree-1 B-spline through the points, parametrised by
-- chord length, so C(u_k) = Q_k exactly and the report's deviations are 0.
-- opts.point_weights (a bsfit.Vector: the host's weights) makes it a NURBS with
-- those weights, which still interpolates (at a knot only one degree-1 basis
-- function is non-zero). opts.fail = true raises an error, opts.outcome = CODE
-- answers `nil, message, CODE`, to test error propagation. The report's count
-- is the number of control points (one per point here), as the real strategies'.
local bs = require "bsfit"

local M = {}

local function chord_knots(P)
  local n, d = #P, P:dim()
  local u, len = { 0 }, 0
  local prev = { P:get(1) }
  for i = 2, n do
    local q, s = { P:get(i) }, 0
    for j = 1, d do s = s + (q[j] - prev[j]) ^ 2 end
    len = len + math.sqrt(s)
    u[i], prev = len, q
  end
  assert(len > 0, "test_strategy: all points coincide")
  local U = { 0 }
  for i = 1, n do U[i + 1] = u[i] / len end
  U[n + 2] = 1
  return U
end

function M.run(P, opts)
  opts = opts or {}
  if opts.fail then error("test_strategy: asked to fail") end
  if opts.outcome then return nil, "no good fit for these points", opts.outcome end
  assert(#P >= 2, "test_strategy: needs at least 2 points")
  local c = bs.curve.new { degree = 1, knots = chord_knots(P), control_points = P,
                           weights = opts.point_weights }
  return c, { rms = 0, max = 0, count = #P, start_index = opts.start or 1 }
end

return M
