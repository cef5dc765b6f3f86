-- exchange_cases.lua
-- The curves and surfaces of test_exchange.sh, and the comparison of what a real reader
-- (OpenCASCADE, ezdxf) evaluates with bsfit's own evaluation.
--   bsfit exchange_cases.lua gen DIR
--     writes DIR/<case>.json (the exact object), .step, .iges (and .dxf for curves),
--     DIR/all.step and DIR/all.dxf (every curve in one file), and DIR/cases.txt: one line
--     "curve|surface NAME" per case, in the order of all.step.
--   bsfit exchange_cases.lua check DIR NAME READER_OUTPUT TOL
--     compares the reader's output (occt_read's or dxf_read.py's format: a header line
--     "curve K TYPE ... FIRST LAST" or "surface K ... U1 U2 V1 V2", then points) with the
--     case(s) NAME ("all": every curve of cases.txt, in order). The reader's parameter
--     range is mapped linearly onto ours; it must be ours (same parametrisation) within
--     1e-12 of its length. Points must agree within TOL times the size of the control net.
--     Prints one line per object and exits 1 on any mismatch.
local bs = require "bsfit"

local function rnd(a, b) return a + (b - a) * math.random() end

-- n increasing random knots on [a, b] (the ends included), with gaps of 0.3..1.7 units
local function increasing(n, a, b)
  local t, s = { 0 }, 0
  for i = 2, n do s = s + rnd(0.3, 1.7); t[i] = s end
  for i = 1, n do t[i] = a + (b - a) * t[i] / s end
  return t
end

local function points(n, dim, scale, ox)
  local P = {}
  for i = 1, n do
    local p = {}
    for k = 1, dim do p[k] = (ox or 0) + scale * rnd(-1, 1) end
    P[i] = p
  end
  return P
end

local function weights(n)
  local w = {}
  for i = 1, n do w[i] = rnd(0.4, 2.5) end
  return w
end

-- Clamped knots with interior knots of random spacing, one of them doubled (p >= 2)
local function clamped_knots(p, n, a, b)
  local inner = n - p - 1
  local t = increasing(inner + 2, a, b)
  local U = {}
  for _ = 1, p + 1 do U[#U + 1] = a end
  for i = 2, inner + 1 do U[#U + 1] = t[i] end
  for _ = 1, p + 1 do U[#U + 1] = b end
  if p >= 2 and inner >= 3 then U[p + 3] = U[p + 2] end -- a double knot: C^(p-2) there
  return U
end

local curves = {}
local function add(name, C) curves[#curves + 1] = { name = name, C = C } end

-- every degree 1..5, 2D and 3D, open clamped / open unclamped / periodic, polynomial and
-- rational, random sizes and offsets (seeded: the same cases every run)
local function make_curves()
  math.randomseed(20261124)
  for p = 1, 5 do
    for dim = 2, 3 do
      local scale, ox = 10 ^ rnd(-2, 3), rnd(-100, 100)
      local n = p + 1 + math.random(0, 6)
      local a, b = rnd(-3, 3), 0
      b = a + rnd(0.5, 20)
      add(("open_p%d_%dd"):format(p, dim), bs.curve.new {
        degree = p, knots = clamped_knots(p, n, a, b), control_points = points(n, dim, scale, ox) })
      add(("unclamped_p%d_%dd"):format(p, dim), bs.curve.new {
        degree = p, knots = increasing(n + p + 1, a, b), control_points = points(n, dim, scale, ox) })
      add(("rational_p%d_%dd"):format(p, dim), bs.curve.new {
        degree = p, knots = clamped_knots(p, n, a, b), control_points = points(n, dim, scale, ox),
        weights = weights(n) })
      local N = p + 1 + math.random(1, 8)
      add(("periodic_p%d_%dd"):format(p, dim), bs.curve.new {
        degree = p, periodic = true, knots = increasing(N + 1, a, b),
        control_points = points(N, dim, scale, ox) })
      add(("periodic_rational_p%d_%dd"):format(p, dim), bs.curve.new {
        degree = p, periodic = true, knots = increasing(N + 1, a, b),
        control_points = points(N, dim, scale, ox), weights = weights(N) })
      -- corners: a knot of multiplicity p at the seam and one inside (C0 there), as
      -- the automatic strategy makes them
      local M = 2 * p + 2 + math.random(0, 4)
      local t = increasing(M + 1, a, b)
      for i = 2, p do t[i] = t[1] end
      for i = p + 3, 2 * p + 1 do t[i] = t[p + 2] end
      add(("periodic_corners_p%d_%dd"):format(p, dim), bs.curve.new {
        degree = p, periodic = true, knots = t, control_points = points(M, dim, scale, ox),
        weights = (p % 2 == 0) and weights(M) or nil })
    end
  end
  local h = math.sqrt(0.5)
  add("arc_quarter", bs.curve.new { degree = 2, control_points = { { 1, 0 }, { 1, 1 }, { 0, 1 } },
    weights = { 1, h, 1 } })
  -- the full circle of nine control points (NURBS Book ex. 7.1), radius 25 at (3, -4, 7)
  local ring, rw = {}, {}
  local c9 = { { 1, 0 }, { 1, 1 }, { 0, 1 }, { -1, 1 }, { -1, 0 }, { -1, -1 }, { 0, -1 }, { 1, -1 }, { 1, 0 } }
  for i, q in ipairs(c9) do
    ring[i] = { 3 + 25 * q[1], -4 + 25 * q[2], 7 }
    rw[i] = (i % 2 == 0) and h or 1
  end
  add("circle_9", bs.curve.new { degree = 2, control_points = ring, weights = rw,
    knots = { 0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1 } })
  add("bezier_p4", bs.bezier.new { control_points = points(5, 3, 5) })
end

local surfaces = {}
local function add_surface(name, S) surfaces[#surfaces + 1] = { name = name, S = S } end

local function net(nu, nv, scale, f)
  local P = {}
  for i = 1, nu do
    P[i] = {}
    for j = 1, nv do P[i][j] = f(i, j, scale) end
  end
  return P
end

local function make_surfaces()
  math.randomseed(161)
  for pu = 1, 3 do
    for pv = 1, 3 do
      local nu, nv = pu + 1 + math.random(0, 4), pv + 1 + math.random(0, 4)
      local scale = 10 ^ rnd(-1, 2)
      add_surface(("open_p%d%d"):format(pu, pv), bs.surface.new {
        degree_u = pu, degree_v = pv, knots_u = clamped_knots(pu, nu, 0, rnd(1, 5)),
        knots_v = clamped_knots(pv, nv, rnd(-2, 0), rnd(1, 3)),
        control_points = net(nu, nv, scale, function(i, j, s)
          return { s * (i + rnd(-0.3, 0.3)), s * (j + rnd(-0.3, 0.3)), s * rnd(-1, 1) } end) })
    end
  end
  -- a quarter cylinder: rational quadratic in u, linear in v (exact: radius 4)
  local h = math.sqrt(0.5)
  add_surface("cylinder_quarter", bs.surface.new {
    degree_u = 2, degree_v = 1,
    control_points = { { { 4, 0, 0 }, { 4, 0, 10 } }, { { 4, 4, 0 }, { 4, 4, 10 } }, { { 0, 4, 0 }, { 0, 4, 10 } } },
    weights = { { 1, 1 }, { h, h }, { 1, 1 } } })
  add_surface("rational_p23", bs.surface.new {
    degree_u = 2, degree_v = 3, knots_u = clamped_knots(2, 6, 0, 2), knots_v = clamped_knots(3, 5, 0, 1),
    control_points = net(6, 5, 3, function(i, j, s) return { s * i, s * j, s * rnd(-1, 1) } end),
    weights = net(6, 5, 1, function() return rnd(0.5, 2) end) })
end

-- a surface closed around u (periodic_u, expanded form): the sections of a vase skinned
local function make_skinned()
  local sections = {}
  for k = 1, 5 do
    local z, r = 10 * (k - 1), 8 + 3 * math.sin(k)
    local P = {}
    for i = 1, 9 do
      local a = 2 * math.pi * (i - 1) / 9
      P[i] = { r * math.cos(a) * (1 + 0.2 * math.cos(3 * a)), r * math.sin(a), z }
    end
    sections[k] = bs.curve.new { degree = 3, periodic = true, control_points = P }
  end
  add_surface("skinned_vase", (bs.surface.skin(sections)))
  -- sections with a corner (knot of multiplicity 3) at their start: so is the surface's seam
  for k = 1, 4 do
    local P = {}
    for i = 1, 8 do
      local a = 2 * math.pi * (i - 1) / 8
      P[i] = { (6 + k) * math.cos(a), (4 + k) * math.sin(a), 7 * k }
    end
    sections[k] = bs.curve.new { degree = 3, periodic = true, control_points = P,
      knots = { 0, 0, 0, 0.2, 0.3, 0.5, 0.6, 0.8, 1 } }
  end
  for k = 5, #sections do sections[k] = nil end
  add_surface("skinned_corners", (bs.surface.skin(sections)))
end

local function gen(dir)
  make_curves()
  make_surfaces()
  make_skinned()
  local list, all = {}, {}
  for _, c in ipairs(curves) do
    assert(c.C:write(dir .. "/" .. c.name .. ".json"))
    assert(c.C:write(dir .. "/" .. c.name .. ".step"))
    assert(c.C:write(dir .. "/" .. c.name .. ".iges"))
    if bs.io.write_dxf then assert(c.C:write(dir .. "/" .. c.name .. ".dxf")) end
    list[#list + 1] = "curve " .. c.name
    all[#all + 1] = c.C
  end
  assert(bs.io.write_step(all, dir .. "/all.step"))
  if bs.io.write_dxf then assert(bs.io.write_dxf(all, dir .. "/all.dxf")) end
  for _, s in ipairs(surfaces) do
    assert(s.S:write(dir .. "/" .. s.name .. ".json"))
    assert(s.S:write(dir .. "/" .. s.name .. ".step"))
    assert(s.S:write(dir .. "/" .. s.name .. ".iges"))
    list[#list + 1] = "surface " .. s.name
  end
  local f = assert(io.open(dir .. "/cases.txt", "w"))
  f:write(table.concat(list, "\n"), "\n")
  f:close()
end

-- {kind, fields..., pts = {{x,y,z}...}} records of a reader's output
local function parse(path)
  local recs, cur = {}, nil
  for line in io.lines(path) do
    local kind = line:match("^(%a+) ")
    if kind == "curve" or kind == "surface" then
      local f = {}
      for w in line:gmatch("%S+") do f[#f + 1] = w end
      cur = { kind = kind, f = f, pts = {} }
      recs[#recs + 1] = cur
    elseif kind ~= "end" and cur then
      local x, y, z = line:match("^(%S+) (%S+) (%S+)$")
      if x then cur.pts[#cur.pts + 1] = { tonumber(x), tonumber(y), tonumber(z) } end
    end
  end
  return recs
end

local function net_size(ctrl, dim, n)
  local lo, hi = { math.huge, math.huge, math.huge }, { -math.huge, -math.huge, -math.huge }
  for i = 1, n do
    local x = { ctrl:get(i) }
    for k = 1, dim do lo[k] = math.min(lo[k], x[k]); hi[k] = math.max(hi[k], x[k]) end
  end
  local s = 0
  for k = 1, dim do s = s + (hi[k] - lo[k]) ^ 2 end
  return math.max(math.sqrt(s), 1e-300)
end

local function dist(p, x, y, z) return math.sqrt((p[1] - x) ^ 2 + (p[2] - y) ^ 2 + (p[3] - (z or 0)) ^ 2) end

-- worst distance between the reader's curve record and C, relative to C's size
local function compare_curve(rec, C)
  local first, last = tonumber(rec.f[#rec.f - 1]), tonumber(rec.f[#rec.f])
  local a, b = C:domain()
  local n = #rec.pts
  if math.abs(first - a) > 1e-12 * (b - a) or math.abs(last - b) > 1e-12 * (b - a) then
    return math.huge, ("parameter range [%.17g, %.17g], ours [%.17g, %.17g]"):format(first, last, a, b)
  end
  local ctrl = C:control_points()
  local size, worst = net_size(ctrl, C:dim(), #ctrl), 0
  for i = 1, n do
    local u = a + (b - a) * (i - 1) / (n - 1)
    worst = math.max(worst, dist(rec.pts[i], C:eval(u)) / size)
  end
  return worst, ("%d points"):format(n)
end

local function compare_surface(rec, S)
  local f = rec.f
  local u1, u2, v1, v2 = tonumber(f[#f - 3]), tonumber(f[#f - 2]), tonumber(f[#f - 1]), tonumber(f[#f])
  local ua, ub, va, vb = S:domain()
  if math.abs(u1 - ua) > 1e-12 * (ub - ua) or math.abs(u2 - ub) > 1e-12 * (ub - ua)
      or math.abs(v1 - va) > 1e-12 * (vb - va) or math.abs(v2 - vb) > 1e-12 * (vb - va) then
    return math.huge, ("domain [%g,%g]x[%g,%g], ours [%g,%g]x[%g,%g]"):format(u1, u2, v1, v2, ua, ub, va, vb)
  end
  local ctrl = S:control_points()
  local size = net_size(ctrl, S:dim(), #ctrl)
  local k = math.floor(math.sqrt(#rec.pts) + 0.5)
  local worst = 0
  for i = 1, k do
    for j = 1, k do
      local u, v = ua + (ub - ua) * (i - 1) / (k - 1), va + (vb - va) * (j - 1) / (k - 1)
      worst = math.max(worst, dist(rec.pts[(i - 1) * k + j], S:eval(u, v)) / size)
    end
  end
  return worst, ("%dx%d points"):format(k, k)
end

local function check(dir, name, out, tol)
  local names = {}
  if name == "all" then
    for line in io.lines(dir .. "/cases.txt") do
      local kind, nm = line:match("^(%a+) (%S+)$")
      if kind == "curve" then names[#names + 1] = { kind, nm } end
    end
  else
    for line in io.lines(dir .. "/cases.txt") do
      local kind, nm = line:match("^(%a+) (%S+)$")
      if nm == name then names[1] = { kind, nm } end
    end
  end
  local recs = parse(out)
  if #recs ~= #names then
    print(("FAIL %s: the reader gave %d objects, %d expected"):format(name, #recs, #names))
    os.exit(1)
  end
  local failed = 0
  for i, kn in ipairs(names) do
    local kind, nm = kn[1], kn[2]
    local text = assert(io.open(dir .. "/" .. nm .. ".json")):read("a")
    local worst, what
    if recs[i].kind ~= kind then
      worst, what = math.huge, "a " .. recs[i].kind .. " instead"
    elseif kind == "curve" then
      worst, what = compare_curve(recs[i], assert(bs.curve.from_json(text)))
    else
      worst, what = compare_surface(recs[i], assert(bs.surface.from_json(text)))
    end
    local ok = worst <= tol
    if not ok then failed = failed + 1 end
    print(("%s %s %s: max distance %.3g of the size (%s, %s)"):format(ok and "ok  " or "FAIL", kind, nm,
      worst, what, table.concat(recs[i].f, " ", 3, math.min(#recs[i].f, 9))))
  end
  if failed > 0 then os.exit(1) end
end

local cmd = arg[1]
if cmd == "gen" then gen(arg[2])
elseif cmd == "check" then check(arg[2], arg[3], arg[4], tonumber(arg[5]))
else error("usage: exchange_cases.lua gen DIR | check DIR NAME OUTPUT TOL") end
