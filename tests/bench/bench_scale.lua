-- bench_scale.lua: how each strategy's time grows with the section size, m = 10^3 ..
-- 10^6 points (a noisy star-like section), once per size: the ratio between sizes
-- shows whether the work stays within m log m. carvalho also with its start-point
-- search unbounded (candidates = "all"), up to 10^4 points.
--   bsfit tests/bench/bench_scale.lua [MAX_EXPONENT]   (default 6)
package.path = (arg[0]:match("^(.*)/[^/]*$") or ".") .. "/?.lua;" .. package.path
local bench = require "benchlib"

local clock, section = bench.clock, bench.section

local maxe = tonumber(arg and arg[1]) or 6
local runs = {
  { "auto", {} }, { "periodic", {} }, { "carvalho", {} },
  { "carvalho", { candidates = "all" }, 4, "carvalho (all candidates)" },
}
print(("%-28s %8s %12s %10s %s"):format("strategy", "points", "ms", "ms/point", "notes"))
for _, r in ipairs(runs) do
  local st = require("bsfit.strategy." .. r[1])
  for e = 3, math.min(maxe, r[3] or maxe) do
    local m = 10 ^ e // 1
    local P = section(m)
    collectgarbage()
    local t0 = clock()
    local C, rep = st.run(P, r[2])
    local ms = (clock() - t0) * 1000
    local notes = ("count %d"):format(C:distinct())
    if rep.candidates_tried then
      notes = notes .. (", candidates %d of %d"):format(rep.candidates_tried, rep.candidates_found)
    end
    print(("%-28s %8d %12.1f %10.5f %s"):format(r[4] or r[1], m, ms, ms / m, notes))
  end
end
