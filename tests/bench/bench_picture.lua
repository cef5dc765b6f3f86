-- bench_picture.lua: time and size of a section picture (bsfit.svg) as the section
-- grows: what is drawn is capped (svg.MAX_POINTS points, svg.MAX_SAMPLES curve
-- samples), so the size stays flat while the time grows linearly (one pass over the
-- points for the box, one for the colour scale, one for the worst residuals).
--   bsfit tests/bench/bench_picture.lua [MAXPOINTS]   (default 1e6)
local bs = require "bsfit"
local svg = require "bsfit.svg"

local clock = (bs.parallel and bs.parallel.clock) or os.clock
local top = tonumber(arg and arg[1]) or 1e6

-- A wobbly closed section of m points (and its made-up residuals), 1000 curve samples.
local function section(m)
  local P, res = bs.points.new(m, 2), {}
  for i = 1, m do
    local th = 2 * math.pi * i / m
    local r = 100 + 10 * math.sin(7 * th) + (i % 7) * 0.01
    P:set(i, r * math.cos(th), r * math.sin(th))
    res[i] = (i % 7) * 0.01 + (i % 9973 == 0 and 1 or 0)
  end
  local S = bs.points.new(1000, 2)
  for i = 1, 1000 do
    local th = 2 * math.pi * i / 1000
    local r = 100 + 10 * math.sin(7 * th)
    S:set(i, r * math.cos(th), r * math.sin(th))
  end
  return P, res, S
end

print(("%10s %10s %12s"):format("points", "ms", "bytes"))
local m = 1000
while m <= top do
  local P, res, S = section(m)
  local t0 = clock()
  local text = svg.section { points = P, residuals = res, samples = S, closed = true,
                             max_index = 9973 <= m and 9973 or 1, title = "bench" }
  print(("%10d %10.1f %12d"):format(m, (clock() - t0) * 1000, #text))
  m = m * 10
end
