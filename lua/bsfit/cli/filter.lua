-- lua/bsfit/cli/filter.lua
-- `bsfit filter IN.json -k K [-o OUT.json]` (or `--delta D` instead of -k): smooths a
-- curve by the box filter (SPEC 3) and writes the filtered curve as JSON, plus an SVG
-- of the curve before (grey) and after (red) next to it. Prints the maximum
-- deviation the filter introduced and the total turning and bending energy before
-- and after. Exit status: 0 done, 1 the curve could not be read, filtered or
-- written, 2 usage error.

local bs = require "bsfit"
local report = require "bsfit.report"

local M = {}

local USAGE = [[
usage: bsfit filter IN.json (-k K | --delta D) [-o OUT.json]
  -k K        filter over K knot spans: the moving average of K control points on
              uniform knots, the exact box filter of that width on other knots
  --delta D   filter over [t - D, t + D] (any knots)
  -o OUT.json output (default IN.filtered.json); OUT.svg shows before and after
]]

-- the options, or raises a usage message
function M.parse(args)
  local o, i = {}, 1
  while i <= #args do
    local a = args[i]
    if a == "-k" or a == "--delta" or a == "-o" then
      local v = args[i + 1]
      if v == nil then error(a .. " needs a value", 0) end
      if a == "-o" then
        o.out = v
      else
        local x = tonumber(v)
        if a == "-k" and (math.type(x) ~= "integer" or x < 1) then error("-k needs an integer >= 1", 0) end
        if a == "--delta" and not (x and x > 0 and x < math.huge) then error("--delta needs a number > 0", 0) end
        o[a == "-k" and "k" or "delta"] = x
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
  if (o.k == nil) == (o.delta == nil) then error("give exactly one of -k and --delta", 0) end
  o.out = o.out or (o.input:gsub("%.json$", "") .. ".filtered.json")
  return o
end

-- bs.filter.box(C, arg), its refusals (raised as misuse: the binding's argument
-- errors) turned into the plain reason a command-line user can act on
local function box(C, arg)
  local ok, F, msg = pcall(bs.filter.box, C, arg)
  if not ok then
    local reason = tostring(F):match("bad argument #%d+ to '[^']*' %((.*)%)$")
    error(reason or tostring(F), 0)
  end
  if not F then error(msg, 0) end
  return F
end

-- filters C as asked; returns the filtered curve (raises on failure)
function M.filter(C, o)
  if o.delta then return box(C, { delta = o.delta }) end
  if C:is_uniform() then return box(C, o.k) end
  local a, b = C:domain()
  return box(C, { delta = o.k * (b - a) / (C:count() - C:degree()) / 2 })
end

local function picture(C, F)
  local doc = bs.svg.new(C)
  doc:curve(C, { class = "before" })
  doc:curve(F, { class = "curve" })
  return doc:tostring()
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
    local F = M.filter(C, o)
    report.must_write(o.out, F:to_json())
    report.must_write(o.out:gsub("%.json$", "") .. ".svg", picture(C, F))
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
