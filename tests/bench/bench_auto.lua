-- bench_auto.lua: time of the automatic strategy on a 40-point section and on noisy
-- sections of 10^3 .. 10^5 points (count search and parameter correction included),
-- with the time of each step.
--   bsfit tests/bench/bench_auto.lua
local bs = require "bsfit"
local auto = require "bsfit.strategy.auto"

local clock = (bs.parallel and bs.parallel.clock) or os.clock

-- a noisy star-like section of m points (noise 0.2% of the size)
local function section(m, seed)
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

local function time(f, budget)
  f()
  local best = math.huge
  for _ = 1, 3 do
    local n, t0 = 0, clock()
    repeat f(); n = n + 1 until clock() - t0 > (budget or 0.2)
    best = math.min(best, (clock() - t0) / n * 1000)
  end
  return best
end

for _, m in ipairs { 40, 1000, 10000, 100000 } do
  local P = section(m, 3)
  local _, rep = auto.run(P)
  local ms = time(function() auto.run(P) end, m >= 100000 and 1.0 or 0.2)
  local steps = {}
  for _, name in ipairs(auto.order) do
    steps[#steps + 1] = ("%s %.2f"):format(name, rep.times[name] or 0)
  end
  print(("auto, %6d points: %9.3f ms  (count %d, sigma %.2g; steps in ms: %s)")
        :format(m, ms, rep.count, rep.sigma, table.concat(steps, ", ")))
end
