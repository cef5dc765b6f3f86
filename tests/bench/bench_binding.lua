-- bench_binding.lua: the cost of going through Lua for the hot paths, to compare with
-- bench_binding (the same calls in C on the same data): C:sample(10^6), F:fit on 10^6
-- points, and a weighting rule written in Lua over 10^5 points with P:get / v:set.
--   bsfit tests/bench/bench_binding.lua      (or lua5.4 with LUA_CPATH=build/?.so)
local bs = require "bsfit"
local clock = (bs.parallel and bs.parallel.clock) or os.clock

local m, n = 1000000, 2000
local P, u, w = bs.points.new(m, 2), bs.vector.new(m), bs.vector.new(m)
for i = 1, m do -- the same section as bench_binding.c
  local t = (i - 1) / (m - 1)
  P:set(i, math.cos(6 * t) + 0.001 * math.sin(977 * t), math.sin(5 * t))
  u:set(i, t)
  w:set(i, 1 + 0.5 * math.sin(31 * t))
end
local F = bs.fitter { degree = 3, count = n }
local best_fit, best_sample = math.huge, math.huge
local C
for _ = 1, 5 do
  local t0 = clock()
  C = F:fit(P, u, w)
  best_fit = math.min(best_fit, clock() - t0)
  t0 = clock()
  C:sample(m)
  best_sample = math.min(best_sample, clock() - t0)
end
print(("Lua : sample 10^6 points %8.2f ms   fit 10^6 points, 2000 control points %8.2f ms")
      :format(best_sample * 1e3, best_fit * 1e3))
-- the same fit writing its residuals into one reused Vector (F:fit's 4th argument)
local r, best_reuse = bs.vector.new(m), math.huge
for _ = 1, 5 do
  local t0 = clock()
  C = F:fit(P, u, w, r)
  best_reuse = math.min(best_reuse, clock() - t0)
end
print(("Lua : fit 10^6 points with a reused residual Vector %8.2f ms"):format(best_reuse * 1e3))

-- a weighting rule in Lua: 1 + distance to the centroid, over 10^5 points
local Q = bs.points.new(100000, 2)
for i = 1, #Q do local t = i / #Q; Q:set(i, math.cos(6.283 * t), 0.5 * math.sin(6.283 * t)) end
local best = math.huge
for _ = 1, 5 do
  local t0 = clock()
  local v = bs.vector.new(#Q)
  for i = 1, #Q do
    local x, y = Q:get(i)
    v:set(i, 1 + math.sqrt(x * x + y * y))
  end
  best = math.min(best, clock() - t0)
end
print(("Lua : weighting rule over 10^5 points with P:get / v:set %8.2f ms"):format(best * 1e3))
