-- lua/bsfit/scan/steps.lua
-- The default steps of the scan pipeline (bsfit.scan.pipeline). Each is a function
-- f(x, ctx) that a caller replaces with opts[step]:
--   read(path, ctx)    --> scan {points, triangles, kind}          (bs.scan.read)
--   slice(scan, ctx)   --> list of slices                          (bs.scan.slice)
--   reduce(P, ctx)     --> R, w, cell: a cloud slice's points by centre of mass
--   order(R, ctx)      --> loops {{points, closed, index}}, report (bs.scan.order)
--   fit(P, ctx)        --> C, rep: one loop in its plane (ctx.weights, ctx.closed)
--   to3d(C, slice)     --> the curve mapped into 3D by the slice's frame
--   write(result, ctx) --> writes the run's files (bsfit.scan.output)

local bs = require "bsfit"
local section_output = require "bsfit.section_output"

local M = {}

function M.read(path, ctx)
  local scan, err = bs.scan.read(path, ctx.format)
  if not scan then error(err, 0) end
  return scan
end

function M.slice(scan, ctx)
  local o = { thickness = ctx.thickness, tol = ctx.tol, slices = ctx.slices,
              spacing = ctx.spacing, at = ctx.at }
  if type(ctx.axis) == "table" then o.direction = ctx.axis else o.axis = ctx.axis or "z" end
  return bs.scan.slice(scan, o)
end

-- Default cell: the slab's thickness, so the mean of a cell averages across the slab
-- and the ordering never sees its thickness.
function M.reduce(P, ctx)
  local o = ctx.target and { target = ctx.target } or { cell = ctx.cell or ctx.slab_thickness }
  local R, w, cell = bs.scan.reduce(P, o)
  if not R then error(w, 0) end
  return R, w, cell
end

function M.order(R, ctx)
  local loops, rep = bs.scan.order(R, { method = ctx.order_method or "auto" })
  if not loops then error(rep, 0) end
  return loops, rep
end

function M.fit(P, ctx)
  local o = { degree = ctx.degree }
  if ctx.count then o.count = ctx.count end
  if ctx.weights then o.point_weights = ctx.weights end
  -- the ordering knows whether the loop closes: say so (auto would otherwise decide it
  -- from the gap between the last and first points); carvalho is always closed
  if ctx.closed == false then o.closed = false
  elseif ctx.closed and (ctx.strategy or "auto") ~= "carvalho" then o.closed = true end
  local C, rep = section_output.load_strategy(ctx.strategy or "auto").run(P, o)
  if not C then error(tostring(rep), 0) end
  return C, rep
end

-- The curve C(t) = origin + x(t) u + y(t) v: the same knots and weights, the control
-- points mapped (an affine map commutes with the B-spline sum).
function M.to3d(C, sl)
  local ctrl, p = C:control_points(), C:degree()
  local periodic = C:is_periodic()
  local n = periodic and C:distinct() or #ctrl
  local o, u, v = sl.origin, sl.u, sl.v
  local P3 = {}
  for i = 1, n do
    local x, y = ctrl:get(i)
    P3[i] = { o[1] + x * u[1] + y * v[1], o[2] + x * u[2] + y * v[2], o[3] + x * u[3] + y * v[3] }
  end
  local U = C:knots():values()
  if periodic then -- one period: U[p] .. U[p+N]
    local per = {}
    for i = 1, n + 1 do per[i] = U[p + i] end
    U = per
  end
  local w
  if C:is_rational() then
    local all = C:weights():totable()
    w = {}
    for i = 1, n do w[i] = all[i] end
  end
  return bs.curve.new { degree = p, knots = U, control_points = P3, weights = w,
                        periodic = periodic }
end

-- A rational section (auto writes circular arcs exactly) as the polynomial cubic nearest
-- to it in least squares, within 1e-6 of its size (bs.filter.reduce adds knots until the
-- true distance is that small): skinning interpolates control points across the
-- sections, which rational sections would not survive.
local function polynomial(C, name)
  local x0, x1 = math.huge, -math.huge
  local ctrl = C:control_points()
  for i = 1, #ctrl do
    for _, x in ipairs { ctrl:get(i) } do x0, x1 = math.min(x0, x), math.max(x1, x) end
  end
  local R, rep = bs.filter.reduce(C, { degree = math.max(C:degree(), 3), tol = 1e-6 * (x1 - x0) })
  if not R then error(name .. ": no polynomial within 1e-6 of its size: " .. tostring(rep), 0) end
  return R
end

-- The sections which can be skinned: one closed loop per slice, in slice order, each
-- polynomial; or nil and the reason the surface is not built.
local function skinnable(result)
  local per_slice, order = {}, {}
  for i, c in ipairs(result.curves) do
    local k = c.slice.index
    if not per_slice[k] then
      per_slice[k] = {}
      order[#order + 1] = k
    end
    table.insert(per_slice[k], { curve = result.curves3d[i], name = c.name })
  end
  local sections = {}
  for _, k in ipairs(order) do
    local list = per_slice[k]
    if #list > 1 then
      return nil, ("slice %d has %d loops: one surface cannot pass through them (cut the object "
                   .. "into parts with --at ranges)"):format(k, #list)
    end
    local C = list[1].curve
    if not C:is_periodic() then return nil, list[1].name .. " is not a closed loop" end
    if C:is_rational() then
      local ok, R = pcall(polynomial, C, list[1].name)
      if not ok then return nil, R end
      C = R
    end
    sections[#sections + 1] = C
  end
  if #sections < 2 then return nil, "fewer than two fitted sections" end
  return sections
end

-- Interpolates one surface through the fitted sections (bs.surface.skin): periodic
-- around them, through each exactly. Sets result.surface (and result.skin, the report)
-- or result.surface_message saying why there is none.
function M.skin(result, ctx)
  if ctx.surface == false then return end
  local sections, why = skinnable(result)
  if not sections then
    result.surface_message = why
    return
  end
  -- a section the skinning cannot take (e.g. a corner at its seam: see docs/scan.md) is
  -- reported, not raised: the sections themselves are still written
  local ok, S, rep = pcall(bs.surface.skin, sections)
  if not ok or not S then
    result.surface_message = "skinning failed: " .. tostring(ok and rep or S):gsub("^.-%((.*)%)$", "%1")
    return
  end
  result.surface, result.skin = S, rep
end

function M.write(result, ctx)
  return require("bsfit.scan.output").write(result, ctx)
end

return M
