-- lua/bsfit/cli/cloud.lua
-- `bsfit cloud`: from a scan file (PLY, STL, OBJ mesh; XYZ/CSV cloud) to fitted
-- sections: slices it, reduces and orders each cloud slice, fits every loop in its
-- plane and writes the per-loop files (as `bsfit reconstruct`), the 3D curves in one
-- IGES file and a summary (bsfit.scan.pipeline). Exit code 1 when a slice failed,
-- 2 on a usage or file error.

local pipeline = require "bsfit.scan.pipeline"
local options = require "bsfit.cli_options"

local M = {}

M.usage = [[
usage: bsfit cloud IN.(ply|stl|obj|xyz|csv) -o OUTDIR [options]
  -o OUTDIR        output directory (default bsfit-cloud)
  --axis A         x | y | z, or a direction "dx,dy,dz" (default z)
  --slices N       N planes evenly inside the scan
  --spacing D      planes D apart, centred on the scan
  --at P1,P2,...   planes at these positions (along the axis)
  --thickness T    slab thickness for clouds (default: a quarter of the spacing)
  --tol E          mesh: vertices within E of a plane are on it (default 1e-9 of the size)
  --cell C         reduction cell size (default: the slab thickness)
  --target N       reduce each slab to about N points instead
  --order M        auto | angle | graph (default auto)
  --strategy S     auto | carvalho | periodic | FILE.lua (default auto)
  --degree P       curve degree (default 3)
  --count N        control points per section (default: the strategy's rule)
  --samples K      curve samples written to <name>.csv (default 1000)
  --format LIST    any of json,svg,csv,iges for each loop (default json,svg,csv)
  -j N             process N slices at a time (default 1)
  --skin-tol T     the surface within T of each section, through light uniform cubics
                   (default auto: a mesh's tessellation error, a cloud's noise);
                   0: through the sections exactly
  --no-surface     do not skin the sections into a surface (by default, when every
                   slice gives one closed loop: surface.json, surface.iges, surface.obj)
  -q               no summary line
  -h, --help       this text
]]

local function warn(fmt, ...) io.stderr:write("bsfit cloud: ", fmt:format(...), "\n") end

local number, count, list = options.number, options.positive_integer, options.list

local function axis(s)
  if s == "x" or s == "y" or s == "z" then return s end
  local t = list(s, "--axis")
  if #t ~= 3 then error("--axis must be x, y, z or dx,dy,dz", 0) end
  return t
end

local function formats(s) return options.formats(s, { "json", "svg", "csv", "iges" }) end

local flags = {
  ["-o"] = function(o, v) o.outdir = v end,
  ["--axis"] = function(o, v) o.axis = axis(v) end,
  ["--slices"] = function(o, v) o.slices = count(v, "--slices") end,
  ["--spacing"] = function(o, v) o.spacing = number(v, "--spacing", 0) end,
  ["--at"] = function(o, v) o.at = list(v, "--at") end,
  ["--thickness"] = function(o, v) o.thickness = number(v, "--thickness", 0) end,
  ["--tol"] = function(o, v) o.tol = number(v, "--tol", 0) end,
  ["--cell"] = function(o, v) o.cell = number(v, "--cell", 0) end,
  ["--target"] = function(o, v) o.target = count(v, "--target") end,
  ["--order"] = function(o, v)
    if v ~= "auto" and v ~= "angle" and v ~= "graph" then
      error("--order must be auto, angle or graph", 0)
    end
    o.order_method = v
  end,
  ["--strategy"] = function(o, v) o.strategy = v end,
  ["--degree"] = function(o, v) o.degree = count(v, "--degree") end,
  ["--count"] = function(o, v) o.count = count(v, "--count") end,
  ["--samples"] = function(o, v) o.samples = count(v, "--samples") end,
  ["--format"] = function(o, v) o.formats = formats(v) end,
  ["-j"] = function(o, v) o.jobs = count(v, "-j") end,
  ["--skin-tol"] = function(o, v)
    o.skin_tol = v == "auto" and "auto" or (tonumber(v) == 0 and 0 or number(v, "--skin-tol", 0))
  end,
}

local switches = {
  ["-h"] = function(o) o.help = true end,
  ["--help"] = function(o) o.help = true end,
  ["-q"] = function(o) o.quiet = true end,
  ["--no-surface"] = function(o) o.surface = false end,
}

-- The options and the input file; raises with a usage message.
function M.parse(args)
  local o, input = { outdir = "bsfit-cloud" }, nil
  options.parse(args, o, flags, switches, function(_, a)
    if input then error("one input file only (got '" .. input .. "' and '" .. a .. "')", 0) end
    input = a
  end)
  local help, quiet = o.help, o.quiet
  o.help, o.quiet = nil, nil
  if help then return o, input, true, quiet end
  if not input then error("no input file", 0) end
  local n = (o.slices and 1 or 0) + (o.spacing and 1 or 0) + (o.at and 1 or 0)
  if n ~= 1 then error("give exactly one of --slices, --spacing, --at", 0) end
  if o.cell and o.target then error("give --cell or --target, not both", 0) end
  return o, input, false, quiet
end

function M.main(args)
  local okp, o, input, help, quiet = pcall(M.parse, args or {})
  if not okp then
    warn("%s", tostring(o))
    io.stderr:write(M.usage)
    return 2
  end
  if help then io.stdout:write(M.usage); return 0 end
  local okl, lerr = pcall(require("bsfit.section_output").load_strategy, o.strategy or "auto")
  if not okl then warn("%s", tostring(lerr)); return 2 end
  local ok, result = pcall(pipeline.run, input, o)
  if not ok then warn("%s", tostring(result):gsub("\n.*", "")); return 2 end
  local failed = 0
  for _, r in ipairs(result.rows) do
    if r.status == "error" then
      failed = failed + 1
      warn("%s: slice %d at %.6g: %s", input, r.slice, r.position, r.message)
    end
  end
  if result.surface_message and o.surface ~= false then
    warn("no surface: %s", result.surface_message)
  end
  if not quiet then
    io.stderr:write(("bsfit cloud: %d slices, %d curves, %d failed, %s, results in %s\n")
                    :format(#result.slices, #result.curves3d, failed,
                            result.surface and "surface written" or "no surface", o.outdir))
  end
  return failed > 0 and 1 or 0
end

return M
