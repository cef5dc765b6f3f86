-- lua/bsfit/section_output.lua
-- What `bsfit reconstruct` and `bsfit cloud` share about one fitted section: loading
-- the strategy module, samples of the curve, and the section's files (JSON, IGES, STEP,
-- DXF, CSV of samples, SVG picture).

local bs = require "bsfit"
local report = require "bsfit.report"
local svg = require "bsfit.svg"

local M = {}

local strategies = {}

-- The strategy module: a built-in name or a FILE.lua returning the module.
function M.load_strategy(s)
  if strategies[s] then return strategies[s] end
  local mod
  if s:find("/") or s:match("%.lua$") then
    local chunk, err = loadfile(s, "t")
    if not chunk then error("strategy " .. err, 0) end
    mod = chunk()
  else
    -- "unknown" only when the module itself is not found; any other error while
    -- loading it (a syntax error, a missing module it requires) is reported as itself
    local name = "bsfit.strategy." .. s
    local ok, m = pcall(require, name)
    if not ok then
      if tostring(m):find("module '" .. name .. "' not found", 1, true) then
        error(("unknown strategy '%s' (auto, carvalho, periodic or FILE.lua)"):format(s), 0)
      end
      error(("strategy '%s' failed to load: %s"):format(s, tostring(m)), 0)
    end
    mod = m
  end
  if type(mod) ~= "table" or type(mod.run) ~= "function" then
    error("strategy " .. s .. " does not return a table with a run function", 0)
  end
  strategies[s] = mod
  return mod
end

-- Curve samples as Points: C:sample(k) when bound, else evaluation at k params.
function M.samples(C, k)
  if C.sample then return C:sample(k) end
  local a, b = C:domain()
  local n = C:is_periodic() and k or k - 1
  local u = {}
  for i = 0, k - 1 do u[i + 1] = a + (b - a) * i / n end
  return C:eval_many(bs.vector.new(u))
end

function M.points_csv(S)
  local dim, out = S:dim(), {}
  out[1] = dim == 3 and "x,y,z" or "x,y"
  for i = 1, #S do
    local t = { S:get(i) }
    for k = 1, #t do t[k] = report.num(t[k]) end
    out[i + 1] = table.concat(t, ",")
  end
  return table.concat(out, "\n") .. "\n"
end

function M.control_table(C)
  local ctrl = C:control_points()
  if type(ctrl) ~= "table" then ctrl = ctrl:totable() end
  local N = C:distinct()
  local t = {}
  for i = 1, N do t[i] = ctrl[i] end
  return t
end

-- Writes the requested files of a fitted section.
function M.write_outputs(spec, P, C, rep, S, w)
  local base = spec.outdir .. "/" .. spec.name
  -- a repeated closing point was dropped before the fit (rep.dropped_closing_point): the
  -- picture shows the points the residuals belong to
  if rep.dropped_closing_point and rep.residuals and #rep.residuals < #P then
    P = P:slice(1, #rep.residuals)
  end
  local f = spec.formats
  if f.json then report.must_write(base .. ".json", C:to_json()) end
  for _, ext in ipairs { "iges", "step", "dxf" } do -- CAD exchange, written by C:write
    if f[ext] then
      local ok, err = C:write(base .. "." .. ext)
      if not ok then error("cannot write " .. base .. "." .. ext .. ": " .. tostring(err), 0) end
    end
  end
  if f.csv then report.must_write(base .. ".csv", M.points_csv(S)) end
  if f.svg then
    report.must_write(base .. ".svg", svg.section {
      points = P, samples = S, control = M.control_table(C), closed = C:is_periodic(),
      polygon = spec.polygon, residuals = rep.residuals, weights = w, trust = rep.trust,
      start_index = rep.start_index, max_index = rep.max_index, max = rep.max,
      corners = rep.corners, pieces = rep.pieces, title = spec.name,
      subtitle = ("%d points, %d control points, RMS %.3g, max %.3g (strategy %s)")
        :format(#P, C:distinct(), rep.rms or 0 / 0, rep.max or 0 / 0, spec.strategy) })
  end
end

return M
