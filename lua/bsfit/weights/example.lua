-- lua/bsfit/weights/example.lua
-- An example weighting rule written purely in Lua, to copy when prototyping a
-- rule: weights that grow with a discrete curvature estimate, so the fit follows
-- tight bends more closely while straight runs keep weight 1.
--
--   κ_k = turning angle at Q_k / mean length of its two edges      (closed, cyclic)
--   w_k = 1 + gain * κ_k / mean(κ)                                 (gain = 1)
--
-- Use it as the `weights` step of a strategy:
--   local example = require "bsfit.weights.example"
--   local C, rep = require("bsfit.strategy.periodic").run(P, {weights = example})
--   ... {weights = example.rule{gain = 4}}
-- A rule is any function f(P, ctx) returning a bsfit.Vector (or a table) of #P
-- positive weights; ctx holds the strategy's settings and earlier steps' results.

local bs = require "bsfit"

local M = {}

-- Turning angle (radians, 0 = straight) at point i of the closed polygon and the
-- mean length of its two edges. 2D uses x, y; 3D the angle between the edges.
local function turn_and_spacing(P, i, m)
  local a = { P:get((i - 2) % m + 1) }
  local b = { P:get(i) }
  local c = { P:get(i % m + 1) }
  local e1, e2, l1, l2, dot = {}, {}, 0, 0, 0
  for k = 1, #b do
    e1[k], e2[k] = b[k] - a[k], c[k] - b[k]
    l1, l2 = l1 + e1[k] * e1[k], l2 + e2[k] * e2[k]
    dot = dot + e1[k] * e2[k]
  end
  l1, l2 = math.sqrt(l1), math.sqrt(l2)
  if l1 == 0 or l2 == 0 then return 0, (l1 + l2) / 2 end
  local cosv = math.max(-1, math.min(1, dot / (l1 * l2)))
  return math.acos(cosv), (l1 + l2) / 2
end

-- A rule with the given gain (>= 0).
function M.rule(o)
  o = o or {}
  local gain = o.gain or 1
  if type(gain) ~= "number" or gain < 0 then error("bad option 'gain' (number >= 0 expected)", 2) end
  return function(P)
    local m, kappa, sum = #P, {}, 0
    for i = 1, m do
      local t, s = turn_and_spacing(P, i, m)
      kappa[i] = s > 0 and t / s or 0
      sum = sum + kappa[i]
    end
    local mean, w = sum / m, {}
    for i = 1, m do w[i] = mean > 0 and 1 + gain * kappa[i] / mean or 1 end
    return bs.vector.new(w)
  end
end

-- The rule with gain 1; the module itself is callable as a rule: example(P, ctx).
local default = M.rule()
return setmetatable(M, { __call = function(_, P, ctx) return default(P, ctx) end })
