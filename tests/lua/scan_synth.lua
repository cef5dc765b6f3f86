-- scan_synth.lua
-- Synthetic scans with a known truth, for the scan tests and benchmarks: surfaces of
-- revolution (vase, bottle), swept non-round profiles (airfoil wing, rounded box), a
-- torus (a section with a hole) and two legs (two loops per slice), as triangle meshes
-- (written as PLY ascii / binary LE / BE, STL ascii / binary, OBJ) and as point clouds
-- with Gaussian noise and uneven density (denser on one side, as one scanner view
-- gives). Every shape knows its exact section at height z: `shape.section(z)` returns
-- the list of true loops as dense polylines, and `shape.distance(z, x, y)` the distance
-- from (x, y) to the true section.
--
--   local synth = require "scan_synth"
--   local sh = synth.shapes.vase()
--   local mesh = synth.mesh(sh, {around = 64, rings = 40})   -- {V = {{x,y,z}...}, F = {{i,j,k}...}}
--   synth.write_ply(mesh, "v.ply", "binary_big_endian")
--   local cloud = synth.cloud(sh, {n = 10^5, noise = 0.01, uneven = 4, seed = 7})

local M = {}

-- {======================================================================
-- Random numbers: a small deterministic generator (tests must not depend on math.random's)
-- =======================================================================

function M.rng(seed)
  local s = (seed or 1) % 2147483647
  if s <= 0 then s = s + 2147483646 end
  local r = {}
  function r.uniform()
    s = (s * 48271) % 2147483647
    return s / 2147483647
  end
  function r.normal()
    local u1, u2 = r.uniform(), r.uniform()
    return math.sqrt(-2 * math.log(u1)) * math.cos(2 * math.pi * u2)
  end
  return r
end

-- }======================================================================

-- {======================================================================
-- Shapes. Each: profile(z, t) -> x, y for t in [0, 1) around loop k (loops(z) of them),
-- z range [z0, z1], and a max tessellation error helper.
-- =======================================================================

local function revolution(name, radius, z0, z1)
  return {
    name = name, z0 = z0, z1 = z1, loops = 1, radius = radius,
    point = function(z, t) local r = radius(z); return r * math.cos(2 * math.pi * t), r * math.sin(2 * math.pi * t) end,
    distance = function(z, x, y) return math.abs(math.sqrt(x * x + y * y) - radius(z)) end,
  }
end

M.shapes = {}

function M.shapes.vase()
  return revolution("vase", function(z) return 3 + 0.8 * math.sin(z * 0.6) + 0.3 * math.cos(z * 1.3) end, 0, 10)
end

function M.shapes.bottle()
  -- a body of radius 4, a smooth shoulder to a neck of radius 1.5
  return revolution("bottle", function(z)
    local s = 1 / (1 + math.exp(-(z - 9) * 1.2))
    return 4 * (1 - s) + 1.5 * s
  end, 0, 14)
end

-- A swept profile: the 2D closed curve prof(t) scaled by scale(z).
local function swept(name, prof, scale, z0, z1)
  local sh = { name = name, z0 = z0, z1 = z1, loops = 1 }
  function sh.point(z, t) local x, y = prof(t); local s = scale(z); return s * x, s * y end
  function sh.distance(z, x, y)
    -- distance to a dense polyline of the true section (segments, exact)
    local n, best = 2000, math.huge
    local px, py = sh.point(z, 0)
    for i = 1, n do
      local qx, qy = sh.point(z, i / n)
      local dx, dy = qx - px, qy - py
      local L2 = dx * dx + dy * dy
      local u = L2 > 0 and math.max(0, math.min(1, ((x - px) * dx + (y - py) * dy) / L2)) or 0
      local ex, ey = px + u * dx - x, py + u * dy - y
      best = math.min(best, ex * ex + ey * ey)
      px, py = qx, qy
    end
    return math.sqrt(best)
  end
  return sh
end

-- NACA 0015 with a closed trailing edge, chord 6, centred; t in [0,1): upper then lower.
function M.shapes.wing()
  local function naca(t)
    local s = 2 * t
    local up = s < 1
    local xc = up and (1 - s) or (s - 1)
    xc = (1 - math.cos(math.pi * xc)) / 2 -- cosine spacing: dense at the nose
    local yt = 5 * 0.15 * (0.2969 * math.sqrt(xc) - 0.1260 * xc - 0.3516 * xc ^ 2 + 0.2843 * xc ^ 3 - 0.1036 * xc ^ 4)
    return 6 * (xc - 0.5), up and 6 * yt or -6 * yt
  end
  return swept("wing", naca, function(z) return 1 - 0.03 * z end, 0, 10)
end

-- A rounded box: the superellipse |x/4|^4 + |y/2.5|^4 = 1, in polar form (a bounded
-- speed, so clouds sampled by t have no gaps on the flat sides).
function M.shapes.box()
  local function sq(t)
    local a = 2 * math.pi * t
    local c, s = math.cos(a), math.sin(a)
    local r = 1 / ((c / 4) ^ 4 + (s / 2.5) ^ 4) ^ 0.25
    return r * c, r * s
  end
  return swept("box", sq, function() return 1 end, 0, 8)
end

-- Two legs: cylinders of radius 1.5 centred at x = -3 and x = +3.
function M.shapes.legs()
  local sh = { name = "legs", z0 = 0, z1 = 8, loops = 2 }
  function sh.point(z, t, k)
    local cx = k == 2 and 3 or -3
    return cx + 1.5 * math.cos(2 * math.pi * t), 1.5 * math.sin(2 * math.pi * t)
  end
  function sh.distance(z, x, y)
    return math.min(math.abs(math.sqrt((x + 3) ^ 2 + y * y) - 1.5), math.abs(math.sqrt((x - 3) ^ 2 + y * y) - 1.5))
  end
  return sh
end

-- }======================================================================

-- {======================================================================
-- Meshes: a closed tube per loop (rings of `around` vertices, capped by fans), with
-- triangles oriented outwards.
-- =======================================================================

function M.mesh(sh, o)
  local around, rings = o.around or 48, o.rings or 20
  local V, F = {}, {}
  for k = 1, sh.loops do
    local base = #V
    for r = 0, rings do
      local z = sh.z0 + (sh.z1 - sh.z0) * r / rings
      for i = 0, around - 1 do
        local x, y = sh.point(z, i / around, k)
        V[#V + 1] = { x, y, z }
      end
    end
    local function id(r, i) return base + r * around + (i % around) + 1 end
    for r = 0, rings - 1 do
      for i = 0, around - 1 do
        F[#F + 1] = { id(r, i), id(r, i + 1), id(r + 1, i + 1) }
        F[#F + 1] = { id(r, i), id(r + 1, i + 1), id(r + 1, i) }
      end
    end
    if o.caps ~= false then -- fans to a centre vertex at each end
      for _, r in ipairs { 0, rings } do
        local cx, cy = 0, 0
        for i = 0, around - 1 do cx, cy = cx + V[id(r, i)][1] / around, cy + V[id(r, i)][2] / around end
        V[#V + 1] = { cx, cy, V[id(r, 0)][3] }
        local c = #V
        for i = 0, around - 1 do
          if r == 0 then F[#F + 1] = { c, id(r, i + 1), id(r, i) } else F[#F + 1] = { c, id(r, i), id(r, i + 1) } end
        end
      end
    end
  end
  return { V = V, F = F, around = around, rings = rings }
end

-- A bound on the tessellation error of a mesh of sh at height z: the distance from the
-- true section of the midpoints of ring chords (the sagitta; a diagonal spans a chord of
-- about the same angle, counted twice) plus the error of interpolating linearly between
-- rings (a second difference over the ring spacing, halved: twice the h^2 f''/8 rule).
function M.tess_error(sh, mesh, z)
  local dz = (sh.z1 - sh.z0) / mesh.rings
  local bend, chord = 0, 0
  for k = 1, sh.loops do
    for i = 0, mesh.around - 1 do
      local t = i / mesh.around
      local x0, y0 = sh.point(math.max(sh.z0, z - dz), t, k)
      local x1, y1 = sh.point(z, t, k)
      local x2, y2 = sh.point(math.min(sh.z1, z + dz), t, k)
      bend = math.max(bend, math.sqrt((x0 - 2 * x1 + x2) ^ 2 + (y0 - 2 * y1 + y2) ^ 2) / 2)
      local bx, by = sh.point(z, (i + 1) / mesh.around, k)
      chord = math.max(chord, sh.distance(z, (x1 + bx) / 2, (y1 + by) / 2))
    end
  end
  return 2 * chord + bend + 1e-9
end

-- }======================================================================

-- {======================================================================
-- Clouds: points on the surface with Gaussian noise along the section's plane, and
-- uneven density (a point at angle a is kept with a probability that falls to
-- 1/uneven on the -x side).
-- =======================================================================

function M.cloud(sh, o)
  local r = M.rng(o.seed or 1)
  local n, noise, uneven = o.n or 10000, o.noise or 0, o.uneven or 1
  local P = {}
  while #P < n do
    local z = sh.z0 + (sh.z1 - sh.z0) * r.uniform()
    local k = sh.loops > 1 and (r.uniform() < 0.5 and 1 or 2) or 1
    local x, y = sh.point(z, r.uniform(), k)
    local keep = 1 / uneven + (1 - 1 / uneven) * (x > 0 and 1 or 0.5 + 0.5 * math.cos(math.atan(y, x)))
    if r.uniform() <= keep then
      P[#P + 1] = { x + noise * r.normal(), y + noise * r.normal(), z }
    end
  end
  return P
end

-- }======================================================================

-- {======================================================================
-- Writers
-- =======================================================================

local function open(path) return assert(io.open(path, "wb")) end

-- PLY with extra vertex properties (normals, colour) and an extra element, which the
-- reader must skip; faces as lists (quads are kept as triangles here).
function M.write_ply(mesh, path, format)
  local f = open(path)
  local V, F = mesh.V, mesh.F
  f:write("ply\nformat ", format, " 1.0\ncomment bsfit synthetic scan\n")
  f:write("element vertex ", #V, "\nproperty float nx\nproperty double x\nproperty float y\n")
  f:write("property double z\nproperty uchar red\n")
  f:write("element face ", #F, "\nproperty list uchar int vertex_indices\nproperty float quality\n")
  f:write("element extra 2\nproperty list uint short stuff\nproperty int id\nend_header\n")
  if format == "ascii" then
    for _, v in ipairs(V) do f:write(("0.5 %.17g %.9g %.17g 200\n"):format(v[1], v[2], v[3])) end
    for _, t in ipairs(F) do f:write(("3 %d %d %d 0.25\n"):format(t[1] - 1, t[2] - 1, t[3] - 1)) end
    f:write("2 7 8 1\n0 2\n")
  else
    local e = format == "binary_big_endian" and ">" or "<"
    local parts = {}
    for i, v in ipairs(V) do parts[i] = string.pack(e .. "fdfdB", 0.5, v[1], v[2], v[3], 200) end
    f:write(table.concat(parts))
    parts = {}
    for i, t in ipairs(F) do parts[i] = string.pack(e .. "Biiif", 3, t[1] - 1, t[2] - 1, t[3] - 1, 0.25) end
    f:write(table.concat(parts))
    f:write(string.pack(e .. "Ihhi", 2, 7, 8, 1), string.pack(e .. "Ii", 0, 2))
  end
  f:close()
end

-- header: the 80-byte header of a binary file (some exporters start it with "solid").
function M.write_stl(mesh, path, ascii, header)
  local f = open(path)
  local V = mesh.V
  if ascii then
    f:write("solid synth\n")
    for _, t in ipairs(mesh.F) do
      f:write("  facet normal 0 0 0\n    outer loop\n")
      for k = 1, 3 do -- the binary file's float32 values, exactly
        local v = V[t[k]]
        local x, y, z = string.unpack("<fff", string.pack("<fff", v[1], v[2], v[3]))
        f:write(("      vertex %.17g %.17g %.17g\n"):format(x, y, z))
      end
      f:write("    endloop\n  endfacet\n")
    end
    f:write("endsolid synth\n")
  else
    local h = header or "bsfit synthetic"
    local parts = { h .. (" "):rep(80 - #h), string.pack("<I4", #mesh.F) }
    for _, t in ipairs(mesh.F) do
      local a, b, c = V[t[1]], V[t[2]], V[t[3]]
      parts[#parts + 1] = string.pack("<fff fff fff fff I2", 0, 0, 0, a[1], a[2], a[3], b[1], b[2], b[3],
                                      c[1], c[2], c[3], 0)
    end
    f:write(table.concat(parts))
  end
  f:close()
end

-- OBJ with texture/normal indices and, every other face, negative (relative) indices.
function M.write_obj(mesh, path)
  local f = open(path)
  local nv = #mesh.V
  f:write("# bsfit synthetic\no synth\n")
  for _, v in ipairs(mesh.V) do f:write(("v %.17g %.17g %.17g\n"):format(v[1], v[2], v[3])) end
  f:write("vt 0 0\nvn 0 0 1\n")
  for i, t in ipairs(mesh.F) do
    if i % 2 == 0 then
      f:write(("f %d/1/1 %d//1 %d\n"):format(t[1] - nv - 1, t[2] - nv - 1, t[3] - nv - 1))
    else
      f:write(("f %d/1 %d/1/1 %d\n"):format(t[1], t[2], t[3]))
    end
  end
  f:close()
end

function M.write_xyz(P, path)
  local f = open(path)
  local parts = {}
  for i, p in ipairs(P) do parts[i] = ("%.9g %.9g %.9g"):format(p[1], p[2], p[3]) end
  f:write(table.concat(parts, "\n"), "\n")
  f:close()
end

-- }======================================================================

return M
