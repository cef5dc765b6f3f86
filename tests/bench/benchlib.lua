-- benchlib.lua: what the Lua benchmarks share (not a benchmark itself: scripts/bench.sh
-- runs bench_*.lua). A bench script finds it next to itself:
--   package.path = (arg[0]:match("^(.*)/[^/]*$") or ".") .. "/?.lua;" .. package.path
--   local bench = require "benchlib"
local bs = require "bsfit"

local M = {}

-- wall-clock seconds when the worker pool is there to give them, else CPU seconds
M.clock = (bs.parallel and bs.parallel.clock) or os.clock

-- the least time of `runs` calls of f, in seconds
function M.least(f, runs)
  local best = math.huge
  for _ = 1, runs do
    local t0 = M.clock()
    f()
    best = math.min(best, M.clock() - t0)
  end
  return best
end

-- a seeded generator (the same numbers everywhere): uniform in (0, 1), and Gaussian (Box-Muller)
function M.rng(seed)
  local s = seed or 1
  local function rnd() s = (s * 1103515245 + 12345) % 2147483648; return (s + 0.5) / 2147483648 end
  local function gauss() return math.sqrt(-2 * math.log(rnd())) * math.cos(2 * math.pi * rnd()) end
  return rnd, gauss
end

-- a noisy star-like section of m points (five lobes, size about 2, noise 0.2% of the
-- size), the same for a given seed
function M.section(m, seed)
  local t, _, gauss = {}, M.rng(seed)
  for k = 0, m - 1 do
    local a = 2 * math.pi * k / m
    local r = 1 + 0.15 * math.cos(5 * a)
    t[#t + 1] = { r * math.cos(a) + 0.004 * gauss(), r * math.sin(a) + 0.004 * gauss() }
  end
  return bs.points.new(t)
end

-- a D of radius 10 and m exact samples: its straight side and its half circle sampled at
-- the same spacing
function M.dshape(m)
  local t, nl = {}, math.floor(m * 2 / (2 + math.pi))
  for i = 0, nl - 1 do t[#t + 1] = { -10 + 20 * (i + 0.5) / nl, 0 } end
  for i = 0, m - nl - 1 do
    local a = math.pi * (i + 0.5) / (m - nl)
    t[#t + 1] = { 10 * math.cos(a), 10 * math.sin(a) }
  end
  return bs.points.new(t)
end

return M
