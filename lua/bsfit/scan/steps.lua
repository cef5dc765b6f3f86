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

-- The sagittas (L_a + L_b) θ / 8 at the vertices of a closed polyline, into s: a chord of
-- length L across an arc turning by θ is L θ / 8 from it. On the loop of a plane cut
-- through a mesh the turns gather at the facets' edges (the cut through a facet's own
-- diagonal barely turns), so the chord over both neighbouring segments is the facet's.
local function polyline_sagitta(P, s)
  local m = #P
  for i = 1, m do
    local x0, y0 = P:get((i - 2) % m + 1)
    local x1, y1 = P:get(i)
    local x2, y2 = P:get(i % m + 1)
    local ax, ay, bx, by = x1 - x0, y1 - y0, x2 - x1, y2 - y1
    local la, lb = math.sqrt(ax * ax + ay * ay), math.sqrt(bx * bx + by * by)
    if la > 0 and lb > 0 then
      s[#s + 1] = (la + lb) * math.abs(math.atan(ax * by - ay * bx, ax * bx + ay * by)) / 8
    end
  end
end

-- The distance the surface may keep from the sections (ctx.skin_tol: a number; 0 or false:
-- through them exactly; "auto", the default): what the scan itself is sure of. A mesh:
-- its tessellation error, the upper quartile of its loops' vertex sagittas (the loops are
-- exact cuts of flat facets, and auto follows them facet by facet: hundreds of C0 knots
-- per section; the quartile passes over the few real corners and the facets' diagonals).
-- A cloud: its noise, the median RMS of the section fits.
function M.skin_tolerance(result, ctx)
  local t = ctx.skin_tol
  if t == nil or t == "auto" then
    local s = {}
    if result.scan and result.scan.triangles then
      for _, sl in ipairs(result.slices or {}) do
        for _, P in ipairs(sl.loops or {}) do polyline_sagitta(P, s) end
      end
    else
      for _, r in ipairs(result.rows) do if r.rms then s[#s + 1] = r.rms end end
    end
    table.sort(s)
    local mesh = result.scan and result.scan.triangles
    t = #s > 0 and s[mesh and (3 * #s + 3) // 4 or (#s + 1) // 2] or 0
  end
  return t or 0
end

-- Skins the fitted sections into one surface (bs.surface.skin): periodic around them,
-- within M.skin_tolerance of each (through light uniform cubics; exactly when that is 0 or
-- no cubic count keeps it). Sets result.surface (and result.skin, the report, with
-- skin.tol) or result.surface_message saying why there is none.
function M.skin(result, ctx)
  if ctx.surface == false then return end
  local sections, why = skinnable(result)
  if not sections then
    result.surface_message = why
    return
  end
  local tol = M.skin_tolerance(result, ctx)
  -- a section the skinning cannot take is reported, not raised: the sections themselves
  -- are still written
  local ok, S, rep = pcall(bs.surface.skin, sections, { tol = tol })
  if not ok or not S then
    result.surface_message = "skinning failed: " .. tostring(ok and rep or S):gsub("^.-%((.*)%)$", "%1")
    return
  end
  rep.tol, rep.sections = tol, sections
  result.surface, result.skin = S, rep
end

function M.write(result, ctx)
  return require("bsfit.scan.output").write(result, ctx)
end

return M
