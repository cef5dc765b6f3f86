-- run.lua
-- Runs one Lua test file: `lua5.4 run.lua test_x.lua` or `bsfit run.lua test_x.lua`.
-- The test file registers tests with require("tap").test; exit status 0 when all pass.

local here = (arg and arg[0] or ""):match("^(.*)[/\\]") or "."
package.path = here .. "/?.lua;" .. package.path

local file = arg and arg[1]
if not file then
  io.stderr:write("usage: run.lua TESTFILE.lua\n")
  os.exit(2)
end

local T = require "tap"
local chunk, err = loadfile(file)
if not chunk then
  print("not ok 1 - load " .. file)
  print("# " .. err)
  print("0 passed, 1 failed")
  os.exit(1)
end
local loaded, lerr = pcall(chunk)
if not loaded then
  print("not ok 1 - run " .. file)
  print("# " .. tostring(lerr))
  print("0 passed, 1 failed")
  os.exit(1)
end
local _, failed = T.run()
os.exit(failed == 0 and 0 or 1)
