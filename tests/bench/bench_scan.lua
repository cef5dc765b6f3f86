-- bench_scan.lua: the scan pipeline at scale (run with ./build/bsfit tests/bench/bench_scan.lua [JOBS]).
--   1. a cloud of 10^6 points on a vase (noise 0.01), binary PLY: read, 50 slices, reduce,
--      order, fit, 3D curves, every file written -- the whole `bsfit cloud` pipeline, -j JOBS
--      (default 2); target < 2 s;
--   2. a mesh of 10^6 triangles (a vase of 1000 x 500 quads), binary PLY: read, then 100 exact
--      slices; target < 1 s for the slicing; the whole pipeline is reported too, with the
--      surface's net (light within the tessellation error: 43 x 100, not the exact 51399);
--   3. reading 10^7 vertices (binary PLY, then ASCII PLY).
-- Times are wall clock (bs.parallel.clock); best of 3 for the timed kernels.
local bs = require "bsfit"
local here = (arg and arg[0] or ""):match("^(.*)/tests/bench/[^/]*$") or "."
package.path = here .. "/tests/lua/?.lua;" .. here .. "/lua/?.lua;" .. here .. "/tests/bench/?.lua;"
               .. package.path
local synth = require "scan_synth"
local bench = require "benchlib"
local pipeline = require "bsfit.scan.pipeline"
local jobs = tonumber(arg and arg[1]) or 2

local function tmpdir()
  local d = os.tmpname()
  os.remove(d)
  os.execute("mkdir -p '" .. d .. "'")
  return d
end
local DIR = tmpdir()

local function best(n, f) return bench.least(f, n) end

-- a binary PLY of a cloud of n points on the vase, written with string.pack by chunks
local function write_cloud(path, n)
  local sh, r = synth.shapes.vase(), synth.rng(5)
  local f = assert(io.open(path, "wb"))
  f:write("ply\nformat binary_little_endian 1.0\nelement vertex ", n,
          "\nproperty float x\nproperty float y\nproperty float z\nend_header\n")
  local parts = {}
  for i = 1, n do
    local z = 10 * r.uniform()
    local x, y = sh.point(z, r.uniform())
    parts[#parts + 1] = string.pack("<fff", x + 0.01 * r.normal(), y + 0.01 * r.normal(), z)
    if #parts == 65536 then f:write(table.concat(parts)); parts = {} end
  end
  f:write(table.concat(parts))
  f:close()
end

local function write_mesh(path, around, rings)
  local m = synth.mesh(synth.shapes.vase(), { around = around, rings = rings })
  synth.write_ply(m, path, "binary_little_endian")
  return #m.F
end

print(("bench_scan (-j %d)"):format(jobs))
local cloud = DIR .. "/cloud.ply"
write_cloud(cloud, 10 ^ 6)
local t = best(3, function() assert(bs.scan.read(cloud)) end)
print(("cloud 10^6 points: read %.3f s"):format(t))
local res
t = best(3, function()
  res = pipeline.run(cloud, { slices = 50, outdir = DIR .. "/cloud_out", jobs = jobs })
end)
local ok = 0
for _, r in ipairs(res.rows) do if r.status == "ok" then ok = ok + 1 end end
print(("cloud 10^6 points, 50 slices, whole pipeline -j %d: %.3f s (%d sections ok; target < 2 s)"):format(jobs, t, ok))
print(("  of which: read to the last fit %.3f s, skin %.3f s (%d x %d net, tol %.3g), files %.3f s")
  :format(res.ms / 1000, res.step_ms.skin / 1000, res.surface and res.surface:count() or 0,
          res.surface and select(2, res.surface:count()) or 0, res.skin and res.skin.tol or 0,
          res.step_ms.write / 1000))

local mesh = DIR .. "/mesh.ply"
local nt = write_mesh(mesh, 1000, 500)
local scan
t = best(3, function() scan = assert(bs.scan.read(mesh)) end)
print(("mesh %d triangles: read %.3f s"):format(nt, t))
local slices
t = best(3, function() slices = bs.scan.slice(scan, { axis = "z", slices = 100 }) end)
local loops = 0
for _, s in ipairs(slices) do loops = loops + #s.loops end
print(("mesh %d triangles, 100 slices: %.3f s (%d loops; target < 1 s)"):format(nt, t, loops))
-- the whole pipeline on the mesh: its loops are 2000 points each (auto took 13 s on some of
-- them before arc length stopped over-refining tiny pieces; tests/bench/bench_auto.lua)
t = best(1, function()
  res = pipeline.run(mesh, { slices = 100, outdir = DIR .. "/mesh_out", jobs = jobs })
end)
local info = require("bsfit.scan.output").surface_info(res) or {}
print(("mesh, 100 slices, whole pipeline -j %d: %.3f s (skin %.3f s, files %.3f s; net %s x %s%s, "
  .. "tol %.3g, max_deviation %.3g)")
  :format(jobs, t, res.step_ms.skin / 1000, res.step_ms.write / 1000, info.control_points_u or "-",
          info.control_points_v or "-", info.exact and ", exact" or "", info.tol or 0,
          info.max_deviation or 0))

-- the same cloud as text: XYZ and ASCII PLY
do
  local S = assert(bs.scan.read(cloud)).points
  local parts, hdr = {}, ("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\n"
    .. "property float y\nproperty float z\nend_header\n"):format(#S)
  for i = 1, #S do parts[i] = ("%.7g %.7g %.7g"):format(S:get(i)) end
  local text = table.concat(parts, "\n") .. "\n"
  local f = assert(io.open(DIR .. "/cloud.xyz", "wb")); f:write(text); f:close()
  f = assert(io.open(DIR .. "/cloud_a.ply", "wb")); f:write(hdr, text); f:close()
  t = best(3, function() assert(bs.scan.read(DIR .. "/cloud.xyz")) end)
  print(("cloud 10^6 points, XYZ text: read %.3f s"):format(t))
  t = best(3, function() assert(bs.scan.read(DIR .. "/cloud_a.ply")) end)
  print(("cloud 10^6 points, ASCII PLY: read %.3f s"):format(t))
end

-- 10^7 vertices: the cloud file ten times over
local big = DIR .. "/big.ply"
write_cloud(big, 10 ^ 7)
t = best(1, function() assert(bs.scan.read(big)) end)
print(("10^7 vertices, binary PLY: read %.3f s"):format(t))
os.execute("rm -rf '" .. DIR .. "'")
