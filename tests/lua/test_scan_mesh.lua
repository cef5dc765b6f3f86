-- test_scan_mesh.lua: reading meshes (PLY ascii / LE / BE, STL ascii / binary, OBJ) and
-- slicing them exactly (bs.scan.read, bs.scan.slice). Truth: the analytic sections of
-- the synthetic shapes of scan_synth.lua, and hand-made meshes for each degenerate case.
local T = require "tap"
local bs = require "bsfit"
local synth = require "scan_synth"

local function tmpdir()
  local d = os.tmpname()
  os.remove(d)
  os.execute("mkdir -p '" .. d .. "'")
  return d
end
local DIR = tmpdir()

local writers = {
  ply_ascii = function(m, p) synth.write_ply(m, p .. ".ply", "ascii"); return p .. ".ply" end,
  ply_le = function(m, p) synth.write_ply(m, p .. ".ply", "binary_little_endian"); return p .. ".ply" end,
  ply_be = function(m, p) synth.write_ply(m, p .. ".ply", "binary_big_endian"); return p .. ".ply" end,
  stl_ascii = function(m, p) synth.write_stl(m, p .. ".stl", true); return p .. ".stl" end,
  stl_binary = function(m, p) synth.write_stl(m, p .. ".stl", false); return p .. ".stl" end,
  obj = function(m, p) synth.write_obj(m, p .. ".obj"); return p .. ".obj" end,
}
local writer_names = { "ply_ascii", "ply_le", "ply_be", "stl_ascii", "stl_binary", "obj" }

local function area(P)
  local a = 0
  for i = 1, #P do
    local x0, y0 = P:get(i)
    local x1, y1 = P:get(i % #P + 1)
    a = a + x0 * y1 - x1 * y0
  end
  return a / 2
end

T.test("every mesh format reads back the same vertices and triangles", function()
  for _, shape in ipairs { "vase", "wing" } do
    local sh = synth.shapes[shape]()
    local m = synth.mesh(sh, { around = 24, rings = 6 })
    for _, w in ipairs(writer_names) do
      local path = writers[w](m, DIR .. "/" .. shape .. "_" .. w)
      local s = assert(bs.scan.read(path))
      T.eq(s.kind, "mesh", w)
      T.eq(#s.points, #m.V, w .. ": vertices (STL: identical corners merged)")
      T.eq(#s.triangles, #m.F, w .. ": triangles")
      -- corners compared by coordinates (STL numbers merged vertices in order of first
      -- use); PLY stores y as float, STL every coordinate: compare at float precision
      local worst = 0
      for i = 1, #m.F, 3 do
        local ids = { s.triangles:get(i) }
        for k = 1, 3 do
          local x, y, z = s.points:get(ids[k])
          local v = m.V[m.F[i][k]]
          worst = math.max(worst, math.abs(x - v[1]), math.abs(y - v[2]), math.abs(z - v[3]))
        end
      end
      T.ok(worst < 1e-5, w .. ": corners off by " .. worst)
    end
  end
end)

T.test("a binary STL whose header starts with 'solid' is read as binary", function()
  local m = synth.mesh(synth.shapes.vase(), { around = 12, rings = 3 })
  synth.write_stl(m, DIR .. "/solid_header.stl", false, "solid exported by some CAD program")
  local s = assert(bs.scan.read(DIR .. "/solid_header.stl"))
  T.eq(#s.triangles, #m.F)
  T.eq(#s.points, #m.V)
end)

T.test("mesh sections lie within the tessellation error of the true sections", function()
  local r = synth.rng(11)
  local cases = { { "vase", 48, 30 }, { "bottle", 64, 28 }, { "wing", 80, 10 }, { "box", 72, 8 },
                  { "legs", 32, 8 }, { "vase", 17, 7 } }
  for ci, c in ipairs(cases) do
    local sh = synth.shapes[c[1]]()
    local m = synth.mesh(sh, { around = c[2], rings = c[3] })
    local path = writers[writer_names[(ci - 1) % #writer_names + 1]](m, DIR .. "/sec" .. ci)
    local scan = assert(bs.scan.read(path))
    local at = {}
    for k = 1, 6 do at[k] = sh.z0 + (sh.z1 - sh.z0) * (0.05 + 0.9 * r.uniform()) end
    at[7] = sh.z0 + (sh.z1 - sh.z0) * 3 / c[3] -- exactly at a ring: vertices on the plane
    local slices = bs.scan.slice(scan, { axis = "z", at = at })
    T.eq(#slices, #at)
    for _, s in ipairs(slices) do
      local what = ("%s z=%.4f"):format(c[1], s.position)
      T.eq(#s.loops, sh.loops, what .. ": loops")
      local bound = synth.tess_error(sh, m, s.position) * 1.001 + 1e-6 -- STL: float coordinates
      for k, P in ipairs(s.loops) do
        T.ok(s.closed[k], what .. ": closed")
        T.ok(area(P) > 0, what .. ": counter-clockwise seen from +z")
        local worst = 0
        for i = 1, #P do
          local x, y = P:get(i)
          worst = math.max(worst, sh.distance(s.position, x, y))
        end
        T.ok(worst <= bound, ("%s: %.3g off the true section (bound %.3g)"):format(what, worst, bound))
        T.ok(#P >= c[2], what .. ": every ring edge crossed")
      end
      T.eq(s.origin[3], s.position)
      T.ok(s.u[1] == 1 and s.v[2] == 1 and s.normal[3] == 1, what .. ": frame (x, y, z)")
    end
  end
end)

-- Hand-made meshes: {points, triangles} tables for the degenerate cases.
local function mesh(V, F) return { points = bs.points.new(V), triangles = bs.scan.triangles(F) } end

local function cube(lo, hi)
  local V = {}
  for i = 0, 7 do
    V[i + 1] = { (i & 1) ~= 0 and hi or lo, (i & 2) ~= 0 and hi or lo, (i & 4) ~= 0 and hi or lo }
  end
  local F = { { 1, 3, 4 }, { 1, 4, 2 }, { 5, 6, 8 }, { 5, 8, 7 }, { 1, 2, 6 }, { 1, 6, 5 },
              { 3, 7, 8 }, { 3, 8, 4 }, { 1, 5, 7 }, { 1, 7, 3 }, { 2, 4, 8 }, { 2, 8, 6 } }
  return mesh(V, F)
end

-- The loop's points as a sorted list of "x,y" strings (rounded), to compare sets.
local function point_set(P)
  local t = {}
  for i = 1, #P do
    local x, y = P:get(i)
    t[i] = ("%.9f,%.9f"):format(x + 0, y + 0):gsub("%-0%.000000000", "0.000000000")
  end
  table.sort(t)
  return table.concat(t, " ")
end

T.test("degenerate: a vertex on the plane gives the vertex itself (octahedron)", function()
  local V = { { 1, 0, 0 }, { 0, 1, 0 }, { -1, 0, 0 }, { 0, -1, 0 }, { 0, 0, 1 }, { 0, 0, -1 } }
  local F = { { 1, 2, 5 }, { 2, 3, 5 }, { 3, 4, 5 }, { 4, 1, 5 }, { 2, 1, 6 }, { 3, 2, 6 }, { 4, 3, 6 }, { 1, 4, 6 } }
  local s = bs.scan.slice(mesh(V, F), { axis = "z", at = { 0 } })[1]
  T.eq(#s.loops, 1)
  T.eq(#s.loops[1], 4)
  T.eq(point_set(s.loops[1]), point_set(bs.points.new { { 1, 0 }, { 0, 1 }, { -1, 0 }, { 0, -1 } }))
  T.ok(s.closed[1] and area(s.loops[1]) > 0)
  -- the apex alone touches: no loop
  T.eq(#bs.scan.slice(mesh(V, F), { axis = "z", at = { 1 } })[1].loops, 0)
end)

T.test("degenerate: an edge on the plane (tetrahedron)", function()
  local V = { { -1, 0, 0 }, { 1, 0, 0 }, { 0, 1, 1 }, { 0.3, -2, -1 } }
  local F = { { 1, 2, 3 }, { 1, 4, 2 }, { 1, 3, 4 }, { 2, 4, 3 } }
  local s = bs.scan.slice(mesh(V, F), { axis = "z", at = { 0 } })[1]
  T.eq(#s.loops, 1)
  T.eq(#s.loops[1], 3)
  T.eq(point_set(s.loops[1]), point_set(bs.points.new { { -1, 0 }, { 1, 0 }, { 0.15, -0.5 } }))
  T.ok(s.closed[1] and area(s.loops[1]) > 0)
end)

T.test("degenerate: a face in the plane (cube top, bottom and middle)", function()
  local C = cube(0, 1)
  local sq = point_set(bs.points.new { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } })
  for _, z in ipairs { 1, 0, 1 - 1e-13 } do
    local s = bs.scan.slice(C, { axis = "z", at = { z } })[1]
    T.eq(#s.loops, 1, "z = " .. z)
    T.eq(point_set(s.loops[1]), sq, "z = " .. z)
    T.ok(s.closed[1] and area(s.loops[1]) > 0)
  end
  local s = bs.scan.slice(C, { axis = "z", at = { 0.5 } })[1]
  T.eq(#s.loops, 1)
  T.near(area(s.loops[1]), 1, 1e-12)
  -- along x and y too: the frames (y, z) and (z, x)
  for _, ax in ipairs { "x", "y" } do
    local sx = bs.scan.slice(C, { axis = ax, at = { 0.25, 1 } })
    for _, q in ipairs(sx) do
      T.eq(#q.loops, 1)
      T.near(area(q.loops[1]), 1, 1e-12)
    end
  end
end)

T.test("a hole in the mesh gives an open chain; nested loops are oriented by depth", function()
  local sh = synth.shapes.vase()
  local m = synth.mesh(sh, { around = 40, rings = 10, caps = false })
  -- remove the 2 triangles of one quad in ring 4
  local F = {}
  for i, t in ipairs(m.F) do if i ~= 4 * 80 + 1 and i ~= 4 * 80 + 2 then F[#F + 1] = t end end
  local z = sh.z0 + (sh.z1 - sh.z0) * 4.5 / 10
  local s = bs.scan.slice(mesh(m.V, F), { axis = "z", at = { z, sh.z0 + (sh.z1 - sh.z0) * 0.75 } })
  T.eq(#s[1].loops, 1)
  T.eq(s[1].closed[1], false, "open where the quad is missing")
  T.eq(#s[1].loops[1], 80 - 1, "every crossing but the missing quad's interior")
  T.eq(s[2].closed[1], true)
  -- a hollow tube: outer loop counter-clockwise, inner clockwise
  local V, G = {}, {}
  for _, R in ipairs { 3, 2 } do
    local base = #V
    for r = 0, 1 do for i = 0, 29 do
      local a = 2 * math.pi * i / 30
      V[#V + 1] = { R * math.cos(a), R * math.sin(a), r }
    end end
    for i = 0, 29 do
      local a, b = base + i + 1, base + (i + 1) % 30 + 1
      G[#G + 1] = { a, b, b + 30 }
      G[#G + 1] = { a, b + 30, a + 30 }
    end
  end
  local h = bs.scan.slice(mesh(V, G), { axis = "z", at = { 0.5 } })[1]
  T.eq(#h.loops, 2)
  local a1, a2 = area(h.loops[1]), area(h.loops[2])
  T.ok((a1 > 0 and a2 < 0 and a1 > -a2) or (a2 > 0 and a1 < 0 and a2 > -a1), "outer CCW, inner CW")
end)

T.test("slicing options: count, spacing, list, direction", function()
  local C = cube(0, 2)
  local s = bs.scan.slice(C, { axis = "z", slices = 3 })
  T.eq(#s, 3)
  T.near(s[1].position, 0.5, 1e-15); T.near(s[3].position, 1.5, 1e-15)
  s = bs.scan.slice(C, { axis = "y", spacing = 0.5 })
  T.eq(#s, 4)
  T.near(s[1].position, 0.25, 1e-15); T.near(s[4].position, 1.75, 1e-15)
  s = bs.scan.slice(C, { direction = { 1, 1, 0 }, at = { math.sqrt(2) } })[1]
  T.eq(#s.loops, 1)
  T.near(area(s.loops[1]), 4 * math.sqrt(2), 1e-9) -- x + y = 2: a 2 sqrt(2) x 2 rectangle
  local n = s.normal
  T.near(n[1] * s.u[1] + n[2] * s.u[2] + n[3] * s.u[3], 0, 1e-15)
  T.near(s.u[2] * s.v[3] - s.u[3] * s.v[2], n[1], 1e-15) -- u x v = n
  T.raises({ match = "exactly one of slices, spacing, at" }, function() bs.scan.slice(C, { slices = 2, spacing = 1 }) end)
  T.raises({ match = "unknown option 'axes'" }, function() bs.scan.slice(C, { axes = "z", slices = 2 }) end)
  T.raises({ match = "axis" }, function() bs.scan.slice(C, { axis = "w", slices = 2 }) end)
end)

T.test("bad mesh files: truncated, malformed, out-of-range faces, NaN vertices", function()
  local sh = synth.shapes.vase()
  local m = synth.mesh(sh, { around = 5, rings = 2, caps = false })
  for _, w in ipairs { "ply_ascii", "ply_le", "ply_be", "stl_binary", "stl_ascii", "obj" } do
    local path = writers[w](m, DIR .. "/trunc_" .. w)
    local f = io.open(path, "rb"); local data = f:read("a"); f:close()
    local cut = path:gsub("(%.%w+)$", "_cut%1")
    local step = math.max(1, #data // 150)
    for len = 0, #data - 1, step do
      f = io.open(cut, "wb"); f:write(data:sub(1, len)); f:close()
      local s, msg, code = bs.scan.read(cut)
      local whole_obj = w == "obj" and s ~= nil -- an OBJ cut at a line end is a valid smaller OBJ
      if not whole_obj then
        T.ok(s == nil, ("%s cut at %d bytes read as valid"):format(w, len))
        T.ok(code == "EFORMAT" or code == "ETOOFEW", ("%s cut at %d: %s %s"):format(w, len, tostring(code), tostring(msg)))
        T.ok(msg:find(cut, 1, true), "the message names the file: " .. tostring(msg))
      end
    end
  end
  local function write(name, text)
    local p = DIR .. "/" .. name
    local f = io.open(p, "wb"); f:write(text); f:close()
    return p
  end
  local hdr = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    .. "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
  local msg = T.fails("EFORMAT", bs.scan.read, write("oor.ply", hdr .. "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"))
  T.ok(msg:find("face 1") and msg:find("out of range"), msg)
  msg = T.fails("EFORMAT", bs.scan.read, write("neg.ply", hdr .. "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n"))
  T.ok(msg:find("out of range"), msg)
  msg = T.fails("ENONFINITE", bs.scan.read, write("nan.ply", hdr .. "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"))
  T.ok(msg:find("vertex 2"), msg)
  msg = T.fails("EFORMAT", bs.scan.read, write("bad.ply", hdr .. "0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n"))
  T.ok(msg:find(":11:") and msg:find("vertex 2"), msg)
  msg = T.fails("EFORMAT", bs.scan.read, write("two.ply", hdr .. "0 0 0\n1 0 0\n0 1 0\n2 0 1\n"))
  T.ok(msg:find("at least 3"), msg)
  msg = T.fails("EFORMAT", bs.scan.read, write("oor.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"))
  T.ok(msg:find("oor.obj:4:") and msg:find("out of range"), msg)
  msg = T.fails("EFORMAT", bs.scan.read, write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"))
  T.ok(msg:find("out of range"), msg)
  T.fails("ENONFINITE", bs.scan.read, write("inf.obj", "v 0 0 0\nv 1 inf 0\nv 0 1 0\nf 1 2 3\n"))
  msg = T.fails("EFORMAT", bs.scan.read, write("notply.ply", "plyx\n"))
  T.ok(msg:find("not a PLY"), msg)
  T.fails("EIO", bs.scan.read, DIR .. "/missing.ply")
  T.fails("EINVAL", bs.scan.read, write("a.unknown", "x"))
  -- a quad face is split into two triangles (a fan)
  local q = "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
    .. "element face 1\nproperty list uchar uint vertex_index\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"
  local s = assert(bs.scan.read(write("quad.ply", q)))
  T.eq(#s.triangles, 2)
  T.eq(select(3, s.triangles:get(2)), 4)
end)

T.test("options a scan cannot honour are errors", function()
  local C = cube(0, 1)
  T.raises({ match = "'thickness' applies to clouds" }, function() bs.scan.slice(C, { slices = 2, thickness = 0.1 }) end)
  T.raises({ match = "'tol' applies to meshes" }, function() bs.scan.slice(C.points, { slices = 2, tol = 0.1 }) end)
  local pipeline = require "bsfit.scan.pipeline"
  T.raises({ match = "cell and target %(reduction%) apply to clouds" }, function()
    pipeline.run("cube", { read = function() return C end, slices = 2, cell = 0.1 })
  end)
  -- a mesh through the pipeline: exact loops, fitted, mapped back to 3D
  local res = pipeline.run("cube", { read = function() return C end, at = { 0.5 } })
  T.eq(#res.rows, 1)
  T.eq(res.rows[1].status, "ok", tostring(res.rows[1].message))
  T.eq(res.rows[1].points_in, 8)
  local x, y, z = res.curves3d[1]:eval(0.25)
  T.near(z, 0.5, 1e-12)
end)
