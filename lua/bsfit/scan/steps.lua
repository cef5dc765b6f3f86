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
  if ctx.closed == false then o.closed = false end
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

function M.write(result, ctx)
  return require("bsfit.scan.output").write(result, ctx)
end

return M
