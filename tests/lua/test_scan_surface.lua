-- test_scan_surface.lua: the scan pipeline's skin step (bsfit.scan.pipeline): from a
-- scanned surface of revolution to one surface through the fitted sections, checked
-- against the true surface (radial distance at 10^4 sample points, which bounds the true
-- distance from above); a slice with two loops gives no surface and says why; the
-- surface's files are written; `surface = false` turns the step off.
local T = require "tap"
local bs = require "bsfit"
local synth = require "scan_synth"
local pipeline = require "bsfit.scan.pipeline"

local function tmpdir()
  local d = os.tmpname()
  os.remove(d)
  os.execute("mkdir -p '" .. d .. "'")
  return d
end

-- The largest radial distance of S's points to a surface of revolution, on a k x k grid
-- inside the sliced height range.
local function max_radial_error(S, sh, k)
  local ua, ub, va, vb = S:domain()
  local worst = 0
  for i = 0, k - 1 do
    for j = 0, k - 1 do
      local x, y, z = S:eval(ua + (ub - ua) * i / k, va + (vb - va) * j / (k - 1))
      worst = math.max(worst, sh.distance(z, x, y))
    end
  end
  return worst
end

local dir = tmpdir()

T.test("a meshed vase: one periodic surface within 2e-3 (12 slices) and 4e-4 (24) of its height", function()
  local sh = synth.shapes.vase()
  local path = dir .. "/vase.ply"
  synth.write_ply(synth.mesh(sh, { around = 128, rings = 80 }), path, "binary_little_endian")
  for _, n in ipairs { 12, 24 } do
    local result = pipeline.run(path, { axis = "z", slices = n })
    T.ok(result.surface, "surface built: " .. tostring(result.surface_message))
    T.ok(result.surface:is_periodic(), "periodic around the sections")
    local err = max_radial_error(result.surface, sh, 100)
    -- 10^4 points; the size is the vase's height, 10
    print("# " .. ("%d slices: max radial error %.3g"):format(n, err))
    T.ok(err < (n == 12 and 0.02 or 0.004), ("%d slices: max radial error %.3g"):format(n, err))
  end
end)

T.test("a cloud of a bottle: the surface follows the truth within the noise", function()
  local sh = synth.shapes.bottle()
  local path = dir .. "/bottle.xyz"
  synth.write_xyz(synth.cloud(sh, { n = 100000, noise = 0.005, seed = 3 }), path)
  local result = pipeline.run(path, { axis = "z", slices = 8, thickness = 0.2, cell = 0.1 })
  T.ok(result.surface, "surface built: " .. tostring(result.surface_message))
  local err = max_radial_error(result.surface, sh, 100)
  print("# " .. ("cloud: max radial error %.3g"):format(err))
  T.ok(err < 0.08, ("max radial error %.3g (noise 0.005, radius 1.5..4)"):format(err))
end)

T.test("two legs: no surface, and the reason names the slice", function()
  local sh = synth.shapes.legs()
  local path = dir .. "/legs.ply"
  synth.write_ply(synth.mesh(sh, { around = 48, rings = 20 }), path, "ascii")
  local result = pipeline.run(path, { axis = "z", slices = 5 })
  T.ok(result.surface == nil, "no surface")
  T.ok(tostring(result.surface_message):find("loops", 1, true), tostring(result.surface_message))
end)

T.test("the surface's files, and surface = false", function()
  local path = dir .. "/vase.ply" -- the first test's
  local out = dir .. "/out"
  local result = pipeline.run(path, { axis = "z", slices = 12, outdir = out })
  for _, ext in ipairs { "json", "iges", "obj" } do
    local f = io.open(out .. "/surface." .. ext)
    T.ok(f and #f:read("a") > 100, "surface." .. ext .. " written")
    if f then f:close() end
  end
  local S = bs.surface.read and bs.surface.read(out .. "/surface.json")
    or bs.surface.from_json(io.open(out .. "/surface.json"):read("a"))
  local x1, y1, z1 = S:eval(0.3, 0.6)
  local x2, y2, z2 = result.surface:eval(0.3, 0.6)
  T.ok(math.abs(x1 - x2) + math.abs(y1 - y2) + math.abs(z1 - z2) == 0, "JSON round trip exact")
  local off = pipeline.run(path, { axis = "z", slices = 12, surface = false })
  T.ok(off.surface == nil and off.surface_message == nil, "surface = false: no step")
end)

T.test("clean up", function() T.ok(os.execute("rm -rf '" .. dir .. "'"), "removed") end)
