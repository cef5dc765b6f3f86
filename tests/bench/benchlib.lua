-- benchlib.lua: what the Lua benchmarks share (not a benchmark itself: scripts/bench.sh
-- runs bench_*.lua). A bench script finds it next to itself:
--   package.path = (arg[0]:match("^(.*)/[^/]*$") or ".") .. "/?.lua;" .. package.path
--   local bench = require "benchlib"
local bs = require "bsfit"

local M = {}

-- wall-clock seconds when the worker pool is there to give them, else CPU seconds
M.clock = (bs.parallel and bs.parallel.clock) or os.clock

-- a noisy star-like section of m points (five lobes, size about 2, noise 0.2% of the
-- size), the same for a given seed
function M.section(m, seed)
  local t, s = {}, seed or 1
  local function rnd() s = (s * 1103515245 + 12345) % 2147483648; return (s + 0.5) / 2147483648 end
  local function gauss() return math.sqrt(-2 * math.log(rnd())) * math.cos(2 * math.pi * rnd()) end
  for k = 0, m - 1 do
    local a = 2 * math.pi * k / m
    local r = 1 + 0.15 * math.cos(5 * a)
    t[#t + 1] = { r * math.cos(a) + 0.004 * gauss(), r * math.sin(a) + 0.004 * gauss() }
  end
  return bs.points.new(t)
end

return M
