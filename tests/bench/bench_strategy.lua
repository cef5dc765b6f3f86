-- bench_strategy.lua: time of the fitting strategies on a 40-point section, and
-- the batch throughput of `bsfit reconstruct`.
--   bsfit tests/bench/bench_strategy.lua [SECTIONS [JOBS [STRATEGY]]]
-- SECTIONS (default 0: skip the batch) 40-point files are written to a temporary
-- directory and reconstructed with -j JOBS (default 2), --format json, --strategy
-- STRATEGY (default auto, the default of bsfit reconstruct).
local bs = require "bsfit"
local carvalho = require "bsfit.strategy.carvalho"
local periodic = require "bsfit.strategy.periodic"

local clock = (bs.parallel and bs.parallel.clock) or os.clock

-- A 40-point closed section: an ellipse with one flattened side and a little
-- deterministic noise (the kind the paper fits).
local function section(seed)
  local t, s = {}, seed or 1
  local function rnd() s = (s * 1103515245 + 12345) % 2147483648; return s / 2147483648 - 0.5 end
  for k = 0, 39 do
    local a = 2 * math.pi * k / 40
    local x, y = 30 * math.cos(a), 18 * math.sin(a)
    if y < -12 then y = -12 end
    t[#t + 1] = { x + 0.05 * rnd(), y + 0.05 * rnd() }
  end
  return bs.points.new(t)
end

-- Best mean time (ms) of f over a few rounds of about 0.2 s each.
local function time(f)
  f()
  local best = math.huge
  for _ = 1, 3 do
    local n, t0 = 0, clock()
    repeat f(); n = n + 1 until clock() - t0 > 0.2
    best = math.min(best, (clock() - t0) / n * 1000)
  end
  return best
end

local P = section(7)
local nomeasure = { measure = function() return {} end }
print(("carvalho, 40 points (start-point search included): %8.3f ms"):format(time(function() carvalho.run(P) end)))
print(("  without the closest-point deviations:              %8.3f ms")
      :format(time(function() carvalho.run(P, nomeasure) end)))
print(("periodic, 40 points:                                 %8.3f ms"):format(time(function() periodic.run(P) end)))
print(("  without the closest-point deviations:              %8.3f ms")
      :format(time(function() periodic.run(P, nomeasure) end)))
-- the same section with two points down-weighted (point_weights 0.05): the trusted
-- parameters, weights and seam score
local pw = {}
for i = 1, #P do pw[i] = (i == 7 or i == 23) and 0.05 or 1 end
pw = bs.vector.new(pw)
print(("  with 2 of 40 points down-weighted:                 %8.3f ms")
      :format(time(function() periodic.run(P, { point_weights = pw }) end)))
-- the time per step of one run (after the warm-up runs above)
local function steps_of(S)
  local _, rep = S.run(P)
  local t = {}
  for _, s in ipairs(S.order) do t[#t + 1] = ("%s %.3f"):format(s, rep.times[s] or 0) end
  return table.concat(t, ", ")
end
print("carvalho steps (ms, one run): " .. steps_of(carvalho))
print("periodic steps (ms, one run): " .. steps_of(periodic))

local nsec, jobs = tonumber(arg and arg[1]) or 0, tonumber(arg and arg[2]) or 2
local strategy = arg and arg[3] or "auto"
if nsec > 0 then
  local dir = os.tmpname()
  os.remove(dir)
  os.execute("mkdir -p " .. dir .. "/in")
  for i = 1, nsec do
    local Q, out = section(i), { "x,y" }
    for k = 1, #Q do out[#out + 1] = ("%.17g,%.17g"):format(Q:get(k)) end
    local f = assert(io.open(("%s/in/s%06d.csv"):format(dir, i), "w"))
    f:write(table.concat(out, "\n"), "\n")
    f:close()
  end
  local rc = require "bsfit.cli.reconstruct"
  local t0 = clock()
  rc.main { dir .. "/in", "-o", dir .. "/out", "-j", tostring(jobs), "--format", "json", "-q",
            "--strategy", strategy }
  local dt = clock() - t0
  print(("batch (%s): %d sections, -j %d: %.2f s, %.0f sections/s"):format(strategy, nsec, jobs,
        dt, nsec / dt))
  os.execute("rm -rf " .. dir)
end
