-- lua/bsfit/cli/filter.lua
-- `bsfit filter IN.json -k K [-o OUT.json]` (or `--delta D` instead of -k): smooths a
-- curve by the box filter (docs/filtering.md) and writes the filtered curve as JSON, plus an SVG
-- of the curve before (blue) and after (vermilion) next to it, with a legend. Prints the maximum
-- deviation the filter introduced and the total turning and bending energy before
-- and after. `--tol T [--order R] [--degree Q]` smooths to a tolerance instead
-- (bs.filter.smooth: the smoothest kernel filter within T, brought back to degree Q).
-- Exit status: 0 done, 1 the curve could not be read, filtered or written, 2 usage
-- error.

local bs = require "bsfit"
local report = require "bsfit.report"
local svg = require "bsfit.svg"

local M = {}

local USAGE = [[
usage: bsfit filter IN.json (-k K | --delta D | --tol T [--order R] [--degree Q]) [-o OUT.json]
  -k K        filter over K knot spans: the moving average of K control points on
              uniform knots, the exact box filter of that width on other knots
  --delta D   filter over [t - D, t + D] (any knots)
  --tol T     the smoothest curve within distance T of the input that kernel
              filters give (least bending energy), brought back to degree Q
  --order R   with --tol: the kernel order (R box passes; default: searched, 1..4)
  --degree Q  with --tol: the degree of the result (default 3)
  -o OUT.json output (default IN.filtered.json); OUT.svg shows before and after
]]

-- numeric option values: name -> {key, check, message}
local VALUES = {
  ["-k"] = { "k", function(x) return math.type(x) == "integer" and x >= 1 end, "an integer >= 1" },
  ["--delta"] = { "delta", function(x) return x > 0 and x < math.huge end, "a number > 0" },
  ["--tol"] = { "tol", function(x) return x > 0 and x < math.huge end, "a number > 0" },
  ["--order"] = { "order", function(x) return math.type(x) == "integer" and x >= 1 end,
                  "an integer >= 1" },
  ["--degree"] = { "degree", function(x) return math.type(x) == "integer" and x >= 1 end,
                   "an integer >= 1" },
}

-- the options, or raises a usage message
function M.parse(args)
  local o, i = {}, 1
  while i <= #args do
    local a = args[i]
    if VALUES[a] or a == "-o" then
      local v = args[i + 1]
      if v == nil then error(a .. " needs a value", 0) end
      if a == "-o" then
        o.out = v
      else
        local spec, x = VALUES[a], math.tointeger(tonumber(v)) or tonumber(v)
        if not (x and spec[2](x)) then error(a .. " needs " .. spec[3], 0) end
        o[spec[1]] = x
      end
      i = i + 2
    elseif a == "-h" or a == "--help" then
      o.help = true
      i = i + 1
    elseif a:sub(1, 1) == "-" then
      error("unknown option " .. a, 0)
    elseif o.input then
      error("one input curve only", 0)
    else
      o.input, i = a, i + 1
    end
  end
  if o.help then return o end
  if not o.input then error("no input curve", 0) end
  local ways = (o.k and 1 or 0) + (o.delta and 1 or 0) + (o.tol and 1 or 0)
  if ways ~= 1 then error("give exactly one of -k, --delta and --tol", 0) end
  if (o.order or o.degree) and not o.tol then error("--order and --degree go with --tol", 0) end
  o.out = o.out or (o.input:gsub("%.json$", "") .. ".filtered.json")
  return o
end

-- A filter fn(C, arg), its refusals (raised as misuse: the binding's argument errors)
-- turned into the plain reason a command-line user can act on
local function call(fn, C, arg)
  local ok, F, msg = pcall(fn, C, arg)
  if not ok then
    local reason = tostring(F):match("bad argument #%d+ to '[^']*' %((.*)%)$")
    error(reason or tostring(F), 0)
  end
  if not F then error(msg, 0) end
  return F, msg
end

local function box(C, arg) return (call(bs.filter.box, C, arg)) end

-- filters C as asked; returns the filtered curve and, with --tol, the smoothing report
-- (raises on failure)
function M.filter(C, o)
  if o.tol then
    return call(bs.filter.smooth, C, { tol = o.tol, order = o.order, degree = o.degree })
  end
  if o.delta then return box(C, { delta = o.delta }) end
  if C:is_uniform() then return box(C, o.k) end
  local a, b = C:domain()
  return box(C, { delta = o.k * (b - a) / (C:count() - C:degree()) / 2 })
end

-- Before (blue, wide) and after (vermilion, narrower, on top): both visible where they
-- coincide; colours apart for colour-blind readers (Okabe-Ito). docs/pictures.md.
local function picture(C, F, o)
  local k = math.max(400, math.min(2000, 20 * C:count()))
  return svg.curves {
    title = ("bsfit filter: %s"):format(o.input),
    subtitle = ("%s; max deviation %.3g"):format(
      o.tol and ("smoothed within tol %g"):format(o.tol) or
      o.delta and ("delta %g"):format(o.delta) or ("k = %d"):format(o.k), C:max_deviation(F)),
    curves = {
      { samples = C:sample(k), closed = C:is_periodic(), class = "before", colour = "#0072b2",
        width = 4, label = "before" },
      { samples = F:sample(k), closed = F:is_periodic(), class = "after", colour = "#d55e00",
        width = 1.5, label = "after (filtered)" } } }
end

function M.main(args)
  local ok, o = pcall(M.parse, args)
  if not ok then
    io.stderr:write("bsfit filter: ", tostring(o), "\n", USAGE)
    return 2
  end
  if o.help then io.write(USAGE); return 0 end
  local done, err = pcall(function()
    local C, msg = bs.curve.read(o.input)
    if not C then error(o.input .. ": " .. tostring(msg), 0) end
    local F, rep = M.filter(C, o)
    report.must_write(o.out, F:to_json())
    report.must_write(o.out:gsub("%.json$", "") .. ".svg", picture(C, F, o))
    if rep then
      local what = rep.changed and ("kernel order %d, delta %.6g, %d knots added")
                                     :format(rep.order, rep.delta, rep.knots_added)
                   or "nothing smoother within tol: unchanged"
      print(("%s: %s, degree %d -> %d, max distance %.6g (certified bound %.6g, tol %.6g), "
             .. "total turning %.6g -> %.6g, bending energy %.6g -> %.6g")
        :format(o.out, what, C:degree(), F:degree(), rep.max_deviation, rep.bound, o.tol,
                rep.turning_before, rep.turning_after, rep.energy_before, rep.energy_after))
      return
    end
    print(("%s: degree %d -> %d, max deviation %.6g, total turning %.6g -> %.6g, bending energy %.6g -> %.6g")
      :format(o.out, C:degree(), F:degree(), C:max_deviation(F), C:total_turning(), F:total_turning(),
              C:bending_energy(), F:bending_energy()))
  end)
  if not done then
    io.stderr:write("bsfit filter: ", tostring(err), "\n")
    return 1
  end
  return 0
end

return M
