-- lua/bsfit/cli_options.lua
-- Command-line option parsing shared by the subcommands (bsfit reconstruct, bsfit cloud):
-- the value checkers, with messages naming the option, and one loop over the words.
--
--   local options = require "bsfit.cli_options"
--   local o = {}
--   options.parse(args, o, flags, switches, function(o, word) ... end)
--
-- flags[name] = function(o, value): an option with a value (`--name value` or
-- `--name=value`); switches[name] = function(o): an option alone; any other word starting
-- with "-" (but "-" itself) is an unknown option; the rest go to positional(o, word).
-- Every error is raised as a message without position (error(msg, 0)).

local M = {}

function M.positive_integer(s, what)
  local n = math.tointeger(tonumber(s))
  if not n or n < 1 then
    error(("%s must be a positive integer, got '%s'"):format(what, tostring(s)), 0)
  end
  return n
end

-- A finite number (above min when given).
function M.number(s, what, min)
  local x = tonumber(s)
  if not x or x ~= x or x == math.huge or x == -math.huge or (min and not (x > min)) then
    local bound = min and (" > " .. min) or ""
    error(("%s must be a number%s, got '%s'"):format(what, bound, tostring(s)), 0)
  end
  return x
end

-- Numbers separated by commas.
function M.list(s, what)
  local t = {}
  for f in tostring(s):gmatch("[^,]+") do t[#t + 1] = M.number(f, what) end
  if #t == 0 then error(what .. " needs numbers separated by commas", 0) end
  return t
end

-- The set of output formats named in s (comma separated), each one of known (a list).
function M.formats(s, known)
  local ok, f = {}, {}
  for _, name in ipairs(known) do ok[name] = true end
  local names = table.concat(known, ", ")
  for name in tostring(s):gmatch("[^,]+") do
    if not ok[name] then error(("unknown format '%s' (%s)"):format(name, names), 0) end
    f[name] = true
  end
  if next(f) == nil then error("--format needs at least one of " .. names, 0) end
  return f
end

function M.parse(args, o, flags, switches, positional)
  local i = 1
  while i <= #args do
    local a = args[i]
    local name, value = a:match("^(%-%-[%w-]+)=(.*)$")
    name = name or a
    if flags[name] then
      if value == nil then
        i = i + 1
        value = args[i]
        if value == nil then error("option " .. name .. " needs a value", 0) end
      end
      flags[name](o, value)
    elseif switches[a] then
      switches[a](o)
    elseif a:sub(1, 1) == "-" and a ~= "-" then
      error("unknown option '" .. a .. "'", 0)
    else
      positional(o, a)
    end
    i = i + 1
  end
  return o
end

return M
