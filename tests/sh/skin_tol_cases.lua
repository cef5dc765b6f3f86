-- skin_tol_cases.lua OUTDIR: the tolerance skin's cases for tests/sh/test_skin_tol.sh. Scans
-- of a broad set of objects (tests/lua/scan_synth.lua's vase, bottle, rounded box, wing, and
-- a twisted prism and a twisted, tapered ellipse made here), as meshes at several
-- tessellations and as clouds with noise, go through the `bsfit cloud` pipeline at several
-- skin tolerances (auto, and multiples of it). Each run writes its sections (the 3D curves
-- the surface was skinned through) and its surface as JSON, and one line of cases.txt:
--   name tol count max_deviation nsections v_1 ... v_K
-- (count 0: the exact surface). skin_tol_check.py measures the distances with scipy.
local bs = require "bsfit"
local out = assert(arg[1], "usage: skin_tol_cases.lua OUTDIR")
local here = (arg[0]:match("^(.*)/tests/sh/[^/]*$")) or "."
package.path = here .. "/tests/lua/?.lua;" .. here .. "/lua/?.lua;" .. package.path
local synth = require "scan_synth"
local pipeline = require "bsfit.scan.pipeline"

-- A sweep of a closed 2D profile prof(t) turned by twist * z and scaled by 1 + taper * z.
local function sweep(name, prof, twist, taper, z1)
  local sh = { name = name, z0 = 0, z1 = z1, loops = 1 }
  function sh.point(z, t)
    local x, y = prof(t % 1)
    local a, s = twist * z, 1 + taper * z
    return s * (math.cos(a) * x - math.sin(a) * y), s * (math.sin(a) * x + math.cos(a) * y)
  end
  return sh
end

-- A regular n-gon of circumradius R, by arc length.
local function ngon(n, R)
  return function(t)
    local s = t * n
    local i = math.floor(s)
    local f = s - i
    local a0, a1 = 2 * math.pi * i / n, 2 * math.pi * (i + 1) / n
    return R * ((1 - f) * math.cos(a0) + f * math.cos(a1)),
           R * ((1 - f) * math.sin(a0) + f * math.sin(a1))
  end
end

local shapes = {
  vase = synth.shapes.vase(), bottle = synth.shapes.bottle(), box = synth.shapes.box(),
  wing = synth.shapes.wing(),
  prism = sweep("prism", ngon(5, 3), 0.05, -0.03, 8),
  ellipse = sweep("ellipse",
                  function(t)
                    return 3 * math.cos(2 * math.pi * t), 1.8 * math.sin(2 * math.pi * t)
                  end,
                  0.1, 0.04, 8),
}

-- {name, shape, mesh = {around, rings} or cloud = {n, noise}, slices, tolerance factors}
local runs = {
  { "vase-m64x20", "vase", { 64, 20 }, nil, 6, { 1, 0.5 } },
  { "vase-m300x100", "vase", { 300, 100 }, nil, 8, { 1, 3 } },
  { "vase-m1000x500", "vase", { 1000, 500 }, nil, 6, { 1 } },
  { "bottle-m128x40", "bottle", { 128, 40 }, nil, 8, { 1, 0.5 } },
  { "bottle-m600x200", "bottle", { 600, 200 }, nil, 6, { 1 } },
  { "ellipse-m200x60", "ellipse", { 200, 60 }, nil, 8, { 1, 2 } },
  { "prism-m100x40", "prism", { 100, 40 }, nil, 8, { 1 } },
  { "box-m160x40", "box", { 160, 40 }, nil, 6, { 1 } },
  { "vase-c1e-2", "vase", nil, { 60000, 0.01 }, 6, { 1, 0.5 } },
  { "bottle-c2e-3", "bottle", nil, { 60000, 0.002 }, 6, { 1 } },
  { "ellipse-c5e-3", "ellipse", nil, { 60000, 0.005 }, 6, { 1, 2 } },
  { "prism-c3e-3", "prism", nil, { 60000, 0.003 }, 6, { 1 } },
  { "wing-c5e-3", "wing", nil, { 60000, 0.005 }, 6, { 1 } },
  -- meshed wings, light and exact (factor 0): loops with corners 1e-4 of the period apart
  -- at the trailing edge, whose merging once squeezed a piece 2400 times in u
  { "wing-m200x40", "wing", { 200, 40 }, nil, 6, { 1, 0 } },
  { "wing-m120x30", "wing", { 120, 30 }, nil, 5, { 1, 0 } },
  { "wing-m300x50", "wing", { 300, 50 }, nil, 9, { 0 } },
}

local list = assert(io.open(out .. "/cases.txt", "w"))
for _, r in ipairs(runs) do
  local name, sh, mesh, cloud, slices, factors = table.unpack(r)
  local path = out .. "/" .. name .. (mesh and ".ply" or ".xyz")
  if mesh then
    synth.write_ply(synth.mesh(shapes[sh], { around = mesh[1], rings = mesh[2] }), path,
                    "binary_little_endian")
  else
    synth.write_xyz(synth.cloud(shapes[sh], { n = cloud[1], noise = cloud[2], seed = #name }), path)
  end
  local opts = { axis = "z", slices = slices, thickness = cloud and 0.2 or nil,
                 cell = cloud and 0.1 or nil }
  local base = pipeline.run(path, opts)
  local auto = assert(base.skin, name .. ": " .. tostring(base.surface_message)).tol
  for _, f in ipairs(factors) do
    local o = {}
    for k, v in pairs(opts) do o[k] = v end
    o.skin_tol = f * auto
    local res = f == 1 and base or pipeline.run(path, o)
    local tag = ("%s-x%g"):format(name, f)
    local rep = assert(res.skin, tag .. ": " .. tostring(res.surface_message))
    res.surface:write(out .. "/" .. tag .. ".surface.json")
    local v = {}
    for k, C in ipairs(rep.sections) do
      C:write(("%s/%s.section%d.json"):format(out, tag, k))
      v[k] = ("%.17g"):format(rep.v_params[k])
    end
    list:write(("%s %.17g %d %.17g %d %s\n"):format(tag, rep.tol, rep.count or 0,
      rep.max_deviation or 0, #rep.sections, table.concat(v, " ")))
    print(("# %s: tol %.3g, %s, %d sections"):format(tag, rep.tol,
      (rep.count or 0) > 0
        and ("%d columns, max_deviation %.3g"):format(rep.count + 3, rep.max_deviation)
        or "exact", #rep.sections))
  end
end
list:close()
