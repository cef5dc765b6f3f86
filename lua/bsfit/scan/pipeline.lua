-- lua/bsfit/scan/pipeline.lua
-- From a scan file to fitted sections and a surface: read -> slice -> (per slice: reduce
-- -> order -> fit) -> to3d -> skin -> write. Every step is a named function of bsfit.scan.steps and
-- opts[step] replaces it (a skinning step is one more name in M.steps); other keys of
-- opts are the settings below, anything else raises.
--
--   local result = require("bsfit.scan.pipeline").run("vase.ply", {axis = "z", slices = 20,
--                                                                   outdir = "out"})
--
-- A slice that fails becomes an error row (result.rows) and the others still run.
-- With jobs > 1 the slices are processed on worker threads (bs.parallel), one Lua state
-- each; a replaced per-slice step (reduce, order, fit) only exists in the calling state,
-- so the slices then run in it, one after the other.

local bs = require "bsfit"
local report = require "bsfit.report"
local section_output = require "bsfit.section_output"
local steps = require "bsfit.scan.steps"

local M = {}

M.steps = { "read", "slice", "reduce", "order", "fit", "to3d", "skin", "write" }

-- The steps run on the whole result, in order, after every slice is done (each
-- f(result, ctx)): the surface through the sections, then the files.
M.result_steps = { "skin", "write" }

-- Settings and their defaults (nil: unset).
M.settings = {
  format = "auto", axis = "z", slices = false, spacing = false, at = false, thickness = false,
  tol = false, cell = false, target = false, order_method = "auto", strategy = "auto",
  degree = 3, count = false, samples = 1000, formats = false, outdir = false, jobs = 1,
  surface = true, skin_tol = "auto",
}

local clock = (bs.parallel and bs.parallel.clock) or os.clock

-- The run's context: settings, then each step (opts[step] or the default).
function M.context(opts)
  local ctx = {}
  for k, v in pairs(M.settings) do if v ~= false then ctx[k] = v end end
  local is_step = {}
  for _, s in ipairs(M.steps) do is_step[s] = true end
  for k, v in pairs(opts or {}) do
    if not is_step[k] and M.settings[k] == nil then
      error(("unknown option '%s'"):format(tostring(k)), 2)
    end
    ctx[k] = v
  end
  for _, s in ipairs(M.steps) do
    ctx[s] = ctx[s] or steps[s]
    if type(ctx[s]) ~= "function" then error(("step '%s' must be a function"):format(s), 2) end
  end
  ctx.formats = ctx.formats or { json = true, svg = true, csv = true }
  return ctx
end

-- {======================================================================
-- One slice
-- =======================================================================

local function loop_name(sl, k, n)
  local base = ("slice%03d"):format(sl.index)
  return n > 1 and (base .. "_" .. k) or base
end

-- The weights of a loop's points, picked from the reduced weights by the loop's index.
local function loop_weights(w, idx)
  if not w or not idx then return nil end
  local t = {}
  for i, j in ipairs(idx) do t[i] = w:get(j) end
  return bs.vector.new(t)
end

-- Fits one loop; returns its row and the 2D curve (nil when the fit failed).
local function fit_loop(sl, ctx, loop, k, nloops, base_row)
  local row = {}
  for key, val in pairs(base_row) do row[key] = val end
  row.loop, row.loops, row.name = k, nloops, loop_name(sl, k, nloops)
  row.points_reduced, row.closed = #loop.points, loop.closed
  row.points_in = row.points_in or #loop.points -- a mesh's loop is its own input
  local lctx = { weights = loop_weights(base_row.w, loop.index), closed = loop.closed }
  setmetatable(lctx, { __index = ctx })
  row.w = nil
  local ok, C, rep = pcall(ctx.fit, loop.points, lctx)
  if not ok then
    row.status, row.message = "error", tostring(C):gsub("\n.*", "")
    return row
  end
  row.control_points, row.rms, row.max = C:distinct(), rep.rms, rep.max
  row.status = loop.closed and "ok" or "open"
  row.message = loop.closed and "" or "open chain: a hole in the mesh or a C-shaped section"
  if ctx.outdir then
    local spec = { outdir = ctx.outdir, name = row.name, formats = ctx.formats,
                   strategy = tostring(ctx.strategy) }
    section_output.write_outputs(spec, loop.points, C, rep, section_output.samples(C, ctx.samples),
                                 lctx.weights)
  end
  return row, C
end

-- The loops of a slice: a mesh's as cut; a cloud's by reduction and ordering.
local function slice_loops(sl, ctx, row)
  if sl.loops then
    local loops = {}
    for k, P in ipairs(sl.loops) do loops[k] = { points = P, closed = sl.closed[k] } end
    if #loops == 0 then error("the plane does not cut the mesh", 0) end
    return loops
  end
  row.points_in = #sl.points
  if #sl.points == 0 then error("empty slab: no points within the thickness of the plane", 0) end
  local rctx = setmetatable({ slab_thickness = sl.thickness }, { __index = ctx })
  local R, w, cell = ctx.reduce(sl.points, rctx)
  row.cell, row.w = cell, w
  local loops, rep = ctx.order(R, ctx)
  row.order = rep and rep.message
  return loops
end

-- Processes one slice. Never raises: returns its rows (one per loop, or one error row)
-- and the fitted 2D curves by row name.
function M.section(sl, ctx)
  local t0 = clock()
  local base = { slice = sl.index, position = sl.position, status = "ok", message = "" }
  local rows, curves = {}, {}
  local ok, loops = pcall(slice_loops, sl, ctx, base)
  if not ok then
    base.status, base.loops, base.w = "error", 0, nil
    base.message = tostring(loops):gsub("\n.*", "")
    base.name = loop_name(sl, 1, 1)
    return { base }, curves, (clock() - t0) * 1000
  end
  for k, loop in ipairs(loops) do
    local row, C = fit_loop(sl, ctx, loop, k, #loops, base)
    if base.order and base.order ~= "one closed loop" and row.message == "" then
      row.message = base.order -- several loops in one slab: say so
    end
    rows[k] = row
    curves[row.name] = C
  end
  return rows, curves, (clock() - t0) * 1000
end

-- }======================================================================

-- {======================================================================
-- Slices on worker threads
-- =======================================================================

local plain = { "format", "axis", "cell", "target", "order_method", "strategy", "degree", "count",
                "samples", "formats", "outdir" }

-- A slice as one string: its settings and frame as a Lua literal, then its points as raw
-- doubles (P:bytes()), each length-prefixed; escaping megabytes of doubles into a literal
-- and parsing them back would cost more than the fits.
local function pack_slice(sl, ctx)
  local s = { index = sl.index, position = sl.position, thickness = sl.thickness, settings = {},
              closed = sl.closed, mesh = sl.loops ~= nil }
  for _, k in ipairs(plain) do s.settings[k] = ctx[k] end
  local parts = sl.loops or { sl.points }
  local out = { string.pack("<s4I4", report.serialize(s), #parts) }
  for k, P in ipairs(parts) do out[k + 1] = string.pack("<s4", P:bytes()) end
  return table.concat(out)
end

local function unpack_slice(item)
  local meta, n, pos = string.unpack("<s4I4", item)
  local s = report.deserialize(meta)
  local sl, parts = { index = s.index, position = s.position, thickness = s.thickness }, {}
  for k = 1, n do
    local b
    b, pos = string.unpack("<s4", item, pos)
    parts[k] = bs.points.frombytes(b, 2)
  end
  if s.mesh then sl.loops, sl.closed = parts, s.closed else sl.points = parts[1] end
  return sl, s.settings
end

-- The worker entry: a packed slice in, its rows and curves (JSON) out.
function M.section_serialized(item)
  local sl, settings = unpack_slice(item)
  local rows, curves, ms = M.section(sl, M.context(settings))
  local json = {}
  for name, C in pairs(curves) do json[name] = C:to_json() end
  return report.serialize { rows = rows, curves = json, ms = ms }
end

local function run_parallel(slices, ctx)
  local items = {}
  for i, sl in ipairs(slices) do items[i] = pack_slice(sl, ctx) end
  local res, errs = bs.parallel.map("bsfit.scan.pipeline", "section_serialized", items, ctx.jobs)
  local out = {}
  for i, sl in ipairs(slices) do
    if res[i] then
      local r = report.deserialize(res[i])
      local curves = {}
      for name, j in pairs(r.curves) do curves[name] = bs.curve.from_json(j) end
      out[i] = { rows = r.rows, curves = curves, ms = r.ms }
    else
      out[i] = { rows = { { slice = sl.index, position = sl.position, status = "error", loops = 0,
                            name = loop_name(sl, 1, 1),
                            message = "worker: " .. tostring(errs and errs[i]):gsub("\n.*", "") } },
                 curves = {}, ms = 0 }
    end
  end
  return out
end

-- }======================================================================

local function custom_slice_steps(ctx)
  return ctx.reduce ~= steps.reduce or ctx.order ~= steps.order or ctx.fit ~= steps.fit
end

-- Every slice, then the 3D curves in slice order.
local function process(slices, ctx)
  local per
  if (ctx.jobs or 1) > 1 and #slices > 1 and bs.parallel and not custom_slice_steps(ctx) then
    per = run_parallel(slices, ctx)
  else
    per = {}
    for i, sl in ipairs(slices) do
      local rows, curves, ms = M.section(sl, ctx)
      per[i] = { rows = rows, curves = curves, ms = ms }
    end
  end
  local result = { rows = {}, curves = {}, curves3d = {}, timing = {} }
  for i, sl in ipairs(slices) do
    result.timing[i] = { slice = sl.index, ms = per[i].ms }
    for _, row in ipairs(per[i].rows) do
      result.rows[#result.rows + 1] = row
      local C = per[i].curves[row.name]
      if C then
        result.curves[#result.curves + 1] = { name = row.name, curve = C, slice = sl }
        result.curves3d[#result.curves3d + 1] = ctx.to3d(C, sl)
      end
    end
  end
  return result
end

-- Runs the whole pipeline on the scan file at input. Returns the result: rows (the
-- summary), curves ({name, curve (2D), slice}), curves3d, slices, scan, timing (per slice),
-- ms (read to the last slice) and step_ms (each result step).
function M.run(input, opts)
  local ctx = M.context(opts)
  local t0 = clock()
  if ctx.outdir and bs.io and bs.io.mkdir then -- the output directory, made when missing
    assert(bs.io.mkdir(ctx.outdir))
  end
  local scan = ctx.read(input, ctx)
  -- options the scan cannot honour are errors, never silently ignored
  if scan.triangles and (ctx.cell or ctx.target or ctx.thickness) then
    error(("%s apply to clouds; %s is a mesh, cut exactly"):format(
      ctx.thickness and "thickness (slabs)" or "cell and target (reduction)", tostring(input)), 0)
  elseif not scan.triangles and ctx.tol then
    error(("tol applies to meshes; %s is a cloud"):format(tostring(input)), 0)
  end
  local slices = ctx.slice(scan, ctx)
  local result = process(slices, ctx)
  result.input, result.scan, result.slices = input, scan, slices
  result.ms = (clock() - t0) * 1000
  result.step_ms = {} -- milliseconds of each result step (skin, write), for benchmarks
  for _, step in ipairs(M.result_steps) do
    local t1 = clock()
    ctx[step](result, ctx)
    result.step_ms[step] = (clock() - t1) * 1000
  end
  return result
end

return M
