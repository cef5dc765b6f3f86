-- lua/bsfit/scan/output.lua
-- The run's files of the scan pipeline (its `write` step): summary.csv and
-- summary.json (one row per loop, or per failed slice), timing.csv (milliseconds only
-- there, so the other files do not depend on -j), sections.iges (every fitted loop as
-- a 3D entity 126, in slice order) and sections.svg (the loops in their planes, one
-- colour per slice), and when the sections make one surface, surface.json, surface.iges
-- (entity 128), surface.obj (a closed triangle mesh) and surface.svg (a wireframe preview
-- with the sections). Every file is written atomically.

local bs = require "bsfit"
local report = require "bsfit.report"
local plot = require "bsfit.plot"
local plot_num = plot.num

local M = {}

M.columns = { "slice", "position", "loop", "loops", "closed", "points_in", "cell", "points_reduced",
              "control_points", "rms", "max", "status", "message", "name" }

-- What the skinned surface is: its control net, the tolerance it was built to and how far
-- from the sections it is (0: through them exactly); nil without a surface.
function M.surface_info(result)
  local S, rep = result.surface, result.skin
  if not S then return nil end
  local nu, nv = S:count()
  return { control_points_u = nu, control_points_v = nv, tol = rep.tol or 0,
           exact = not rep.count or rep.count == 0, max_deviation = rep.max_deviation or 0 }
end

local function summary(dir, result, ctx)
  report.must_write(dir .. "/summary.csv", report.csv(M.columns, result.rows))
  local clean = {}
  for i, r in ipairs(result.rows) do
    local c = {}
    for _, k in ipairs(M.columns) do c[k] = r[k] end
    clean[i] = c
  end
  report.must_write(dir .. "/summary.json", report.json {
    input = result.input, kind = result.scan and result.scan.kind, strategy = ctx.strategy,
    degree = ctx.degree, sections = clean, surface = result.surface ~= nil,
    surface_message = result.surface_message, surface_info = M.surface_info(result) } .. "\n")
  local timing = {}
  for i, t in ipairs(result.timing) do
    timing[i] = { slice = t.slice, ms = ("%.3f"):format(t.ms) }
  end
  report.must_write(dir .. "/timing.csv", report.csv({ "slice", "ms" }, timing))
end

-- The loops drawn in their planes' (u, v) coordinates, overlaid (bsfit.svg's curves:
-- axes, scale bar), coloured by their order along the axis; at most 12 of them named in
-- the legend, evenly spread, the first and the last among them.
local function picture(result, samples)
  local n, curves = #result.curves, {}
  local every = math.max(1, math.ceil((n - 1) / 11))
  for i, c in ipairs(result.curves) do
    local f = n > 1 and (i - 1) / (n - 1) or 0
    local named = (i - 1) % every == 0 or i == n
    curves[i] = { samples = c.curve:sample(samples), closed = c.curve:is_periodic(),
                  colour = plot.viridis(0.9 * f), width = 1.5, class = "section",
                  label = named and ("%s at %s"):format(c.name, plot.num(c.slice.position)) or nil }
  end
  return require("bsfit.svg").curves {
    curves = curves, title = ("sections: %d loop%s in their planes"):format(n, n == 1 and "" or "s"),
    subtitle = "coloured by position along the axis, first dark, last light" }
end

-- The surface's preview (bsfit.svg_surface): its wireframe with the fitted sections on it,
-- seen obliquely about the slicing axis.
function M.surface_picture(result)
  local S, info = result.surface, M.surface_info(result)
  local sl = result.curves[1] and result.curves[1].slice
  return require("bsfit.svg_surface").picture {
    surface = S, sections = result.skin.sections, report = result.skin,
    up = sl and sl.normal or { 0, 0, 1 },
    title = ("surface: %d x %d control points, %d sections"):format(info.control_points_u,
      info.control_points_v, #result.skin.v_params),
    subtitle = info.exact and "through the sections exactly"
      or ("within %s of the sections (skin tolerance %s)"):format(plot_num(info.max_deviation),
                                                               plot_num(info.tol)),
  }
end

function M.write(result, ctx)
  local dir = ctx.outdir
  if not dir then return end
  summary(dir, result, ctx)
  if #result.curves3d > 0 then
    local ok, err = bs.scan.write_iges(dir .. "/sections.iges", result.curves3d)
    if not ok then error("cannot write " .. dir .. "/sections.iges: " .. tostring(err), 0) end
    report.must_write(dir .. "/sections.svg", picture(result, 200))
  end
  if result.surface then -- the skinned surface: JSON, IGES 128, a triangle mesh, a preview
    for _, ext in ipairs { "json", "iges", "obj" } do
      local ok, err = result.surface:write(dir .. "/surface." .. ext)
      if not ok then error("cannot write " .. dir .. "/surface." .. ext .. ": " .. tostring(err), 0) end
    end
    report.must_write(dir .. "/surface.svg", M.surface_picture(result))
  end
end

return M
