-- test_parallel_done.lua: bs.parallel.map's done callback ({threads = n, done = f}):
-- f is called once per item, on the calling thread, with the item's index, its ok flag
-- and its result or error, which equal what map returns; items end in any order but
-- each is reported once; an error in f is raised after the job; the number form of the
-- fourth argument is unchanged. Workers run a module written here: the square of a
-- number, or an error for anything else.
local T = require "tap"
local bs = require "bsfit"
-- the bsfit program sets bs.parallel; under stock lua5.4 it is its own module
local parallel = bs.parallel or require "bsfit.parallel"

local dir = os.tmpname()
os.remove(dir)
os.execute("mkdir -p '" .. dir .. "'")
do
  local f = assert(io.open(dir .. "/pdone_worker.lua", "w"))
  f:write([[return { square = function(s)
    local x = tonumber(s)
    if not x then error("not a number: " .. s) end
    return tostring(x * x)
  end }]])
  f:close()
end
package.path = dir .. "/?.lua;" .. package.path

if not parallel then
  T.test("bs.parallel is present", function() T.ok(false, "this build has no bs.parallel") end)
  return
end

local function items(n, seed)
  local t, s = {}, seed
  for i = 1, n do
    s = (s * 69069 + 1) % 4294967296
    t[i] = (s % 5 == 0) and "{" .. i or tostring(s % 1000) -- about one in five fails
  end
  return t
end

T.test("done: once per item, same results as map returns", function()
  for _, threads in ipairs { 1, 2, 3, 8 } do
    for _, n in ipairs { 1, 2, 7, 40 } do
      local its, seen, count = items(n, n * 31 + threads), {}, 0
      local res, errs = parallel.map("pdone_worker", "square", its, {
        threads = threads,
        done = function(i, ok, out)
          count = count + 1
          T.ok(seen[i] == nil, "item " .. i .. " reported once")
          seen[i] = { ok, out }
        end })
      T.eq(count, n, "every item reported")
      for i = 1, n do
        local want_ok = not its[i]:find("{", 1, true)
        T.eq(seen[i][1], want_ok, "ok flag of item " .. i)
        if want_ok then
          T.eq(seen[i][2], res[i], "result of item " .. i)
          T.eq(tonumber(res[i]), tonumber(its[i]) ^ 2, "the worker's value")
        else
          T.eq(res[i], false); T.eq(seen[i][2], errs[i], "error of item " .. i)
          T.ok(errs[i]:find("not a number: " .. its[i], 1, true), errs[i])
        end
      end
    end
  end
end)

T.test("an error in done is raised after the job; the number form still works", function()
  local calls = 0
  local ok, err = pcall(parallel.map, "pdone_worker", "square", { "1", "2", "3" },
                        { threads = 2, done = function() calls = calls + 1; error("stop here") end })
  T.ok(not ok and tostring(err):find("stop here", 1, true), tostring(err))
  T.eq(calls, 1, "no more calls after the error")
  local res = parallel.map("pdone_worker", "square", { "1", "2" }, 2)
  T.eq(res[1], "1"); T.eq(tonumber(res[2]), 4)
  T.ok(not pcall(parallel.map, "pdone_worker", "square", { "1" }, { done = 3 }), "done must be a function")
end)

T.test("clean up", function() T.ok(os.execute("rm -rf '" .. dir .. "'")) end)
