-- tap.lua
-- A tiny test harness for the bsfit Lua tests (no dependencies): test files register
-- named test functions with T.test; run.lua calls T.run, which prints one TAP-style
-- ok / not ok line per test and a last line "N passed, M failed".

local T = {}
local tests = {}

-- Whether the tests run in the sanitizer build (BSFIT_SANITIZED, set there by CMake): sweeps
-- that ask for it then run a third of their cases, held to floors of their own; memory
-- and undefined behaviour are exercised as well by a third as by all (docs/robustness.md).
T.thinned = os.getenv("BSFIT_SANITIZED") ~= nil

-- Registers a named test; fn raises (through the checks below or any error) to fail.
function T.test(name, fn)
  tests[#tests + 1] = {name = name, fn = fn}
end

local function fail(msg, level)
  error(msg, (level or 1) + 2)
end

function T.ok(cond, msg)
  if not cond then fail(msg or "condition is false") end
  return cond
end

function T.eq(got, want, msg)
  if got ~= want then
    fail(string.format("%s: got %s, want %s", msg or "eq", tostring(got), tostring(want)))
  end
end

-- |got - want| <= tol (tol defaults to 1e-12, relative to max(1, |want|))
function T.near(got, want, tol, msg)
  tol = tol or 1e-12
  if type(got) ~= "number" or not (math.abs(got - want) <= tol * math.max(1, math.abs(want))) then
    fail(string.format("%s: got %s, want %s (tol %g)", msg or "near", tostring(got), tostring(want), tol))
  end
end

-- fn(...) must raise exactly the message `want` (a string), or one matching the
-- Lua pattern want.match when want is a table {match = "..."}. The "chunk:line: "
-- position that luaL_error prepends is not part of the comparison. Call the function
-- under test inside fn (function() C:eval(0/0) end) so that Lua knows its name.
function T.raises(want, fn, ...)
  local ok, err = pcall(fn, ...)
  if ok then fail("expected an error: " .. tostring(type(want) == "table" and want.match or want)) end
  err = tostring(err):gsub("^[^\n]-:%d+: ", "", 1)
  if type(want) == "table" then
    if not err:match(want.match) then fail(string.format("error %q does not match %q", err, want.match)) end
  elseif err ~= want then
    fail(string.format("error %q, want %q", err, want))
  end
  return err
end

-- The 5.4 fail triple: fn(...) returns nil (fail), a message, and the code name `code`
function T.fails(code, fn, ...)
  local r, msg, name = fn(...)
  if r ~= nil then fail("expected fail, got " .. tostring(r)) end
  if type(msg) ~= "string" or msg == "" then fail("fail without a message") end
  if name ~= code then fail(string.format("code %s, want %s (%s)", tostring(name), code, tostring(msg))) end
  return msg
end

-- Runs the registered tests in order; returns passed, failed counts.
function T.run()
  local passed, failed = 0, 0
  for i, t in ipairs(tests) do
    local ok, err = xpcall(t.fn, debug and debug.traceback or tostring)
    if ok then
      passed = passed + 1
      print(string.format("ok %d - %s", i, t.name))
    else
      failed = failed + 1
      print(string.format("not ok %d - %s", i, t.name))
      print("# " .. tostring(err):gsub("\n", "\n# "))
    end
  end
  print(string.format("%d passed, %d failed", passed, failed))
  return passed, failed
end

return T
