-- bench_host.lua: the speed of plain Lua code in the program that runs it. Run it under
-- `bsfit` and under stock `lua5.4` (with LUA_CPATH at the build's bsfit.so): the two should
-- match. They did not while the engine armed a count hook in every call, budget or not:
-- Lua 5.4 then traces every instruction, and scripts ran at half speed. A loop inside a
-- coroutine still carries that hook under bsfit (it is how an interrupt reaches it).
--   bsfit tests/bench/bench_host.lua     (and bsfit --instr-limit 1e12 ...: the budget's cost)
package.path = (arg[0]:match("^(.*)/[^/]*$") or ".") .. "/?.lua;" .. package.path
local bench = require "benchlib"

local N = 10000000
local function loop()
  local s = 0
  for i = 1, N do s = s + i % 7 end
  return s
end

local main = bench.least(loop, 3)
local inside = bench.least(function() coroutine.wrap(loop)() end, 3)
print(("plain Lua, %d iterations: %.0f ms (%.0f M/s); inside a coroutine %.0f ms")
  :format(N, 1000 * main, N / main / 1e6, 1000 * inside))
