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

T.test("a meshed vase skins light: the surface within the tessellation error, 20x fewer columns", function()
  local sh = synth.shapes.vase()
  local path = dir .. "/vase.ply" -- the first test's: 128 around, 80 rings
  local exact = pipeline.run(path, { axis = "z", slices = 24, skin_tol = 0 })
  local light = pipeline.run(path, { axis = "z", slices = 24, outdir = dir .. "/light" })
  local ne, nl = exact.surface:count(), light.surface:count()
  local ee, el = max_radial_error(exact.surface, sh, 100), max_radial_error(light.surface, sh, 100)
  print(("# columns %d exact, %d light (tol %.3g); %.3g and %.3g from the truth"):format(ne, nl,
    light.skin.tol, ee, el))
  -- the mesh's ring chords (radius <= 4.1, 128 around) are 4.1 (1 - cos(pi / 128)) = 1.2e-3 off
  T.ok(light.skin.tol > 3e-4 and light.skin.tol < 2.5e-3, "tol near the tessellation error")
  T.ok(light.skin.count > 0 and nl == light.skin.count + 3, "uniform cubics")
  T.ok(light.skin.max_deviation <= light.skin.tol, "within tol of the sections")
  T.ok(nl * 20 <= ne, ("%d columns against %d"):format(nl, ne))
  T.ok(el <= ee + 2 * light.skin.tol, ("%.3g from the truth"):format(el))
  local f = assert(io.open(dir .. "/light/summary.json"))
  local js = f:read("a")
  f:close()
  T.ok(js:find('"control_points_u":' .. nl, 1, true), "summary.json names the net")
end)

-- A twisted, tapered pentagonal prism: auto fits its loops with C0 knots at the corners
-- (and at every facet); skinning used to refuse such sections.
local function prism()
  local n, R = 5, 3
  local function frame(z) return 0.05 * z, 1 - 0.03 * z end
  local sh = { name = "prism", z0 = 0, z1 = 8, loops = 1 }
  local function corner(i) return R * math.cos(2 * math.pi * i / n), R * math.sin(2 * math.pi * i / n) end
  function sh.point(z, t)
    local s = (t % 1) * n
    local i = math.floor(s)
    local ax, ay = corner(i)
    local bx, by = corner(i + 1)
    local f = s - i
    local a, sc = frame(z)
    local x, y = ax + f * (bx - ax), ay + f * (by - ay)
    return sc * (math.cos(a) * x - math.sin(a) * y), sc * (math.sin(a) * x + math.cos(a) * y)
  end
  function sh.distance(z, x, y)
    local a, sc = frame(z)
    local px = (math.cos(a) * x + math.sin(a) * y) / sc
    local py = (-math.sin(a) * x + math.cos(a) * y) / sc
    local best = math.huge
    for i = 0, n - 1 do
      local ax, ay = corner(i)
      local bx, by = corner(i + 1)
      local dx, dy = bx - ax, by - ay
      local f = math.max(0, math.min(1, ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy)))
      best = math.min(best, math.sqrt((ax + f * dx - px) ^ 2 + (ay + f * dy - py) ^ 2))
    end
    return best * sc
  end
  return sh
end

T.test("a twisted prism's mesh and cloud skin (sections with corners)", function()
  local sh = prism()
  local mpath, cpath = dir .. "/prism.ply", dir .. "/prism.xyz"
  synth.write_ply(synth.mesh(sh, { around = 100, rings = 40 }), mpath, "binary_little_endian")
  synth.write_xyz(synth.cloud(sh, { n = 60000, noise = 0.003, seed = 5 }), cpath)
  for _, run in ipairs {
    { mpath, { axis = "z", slices = 16, skin_tol = 0 }, 0.05 },
    { mpath, { axis = "z", slices = 16 }, 0.05 },
    { cpath, { axis = "z", slices = 10, thickness = 0.2, cell = 0.1 }, 0.1 } } do
    local result = pipeline.run(run[1], run[2])
    T.ok(result.surface, run[1] .. ": surface built: " .. tostring(result.surface_message))
    local err = max_radial_error(result.surface, sh, 100)
    print(("# %s (skin_tol %s): %.3g from the true prism"):format(run[1]:match("[^/]*$"),
      tostring(run[2].skin_tol or "auto"), err))
    T.ok(err < run[3], ("%.3g from the true prism (size 6)"):format(err))
  end
end)

T.test("a cloud of a wing skins light: the trailing edge kept as a C0 knot of the cubics", function()
  -- the sections share their sharp trailing edge: uniform cubics alone round it beyond the
  -- noise at every count (the exact surface, 352 columns, came back); with the edge as a C0
  -- knot of every cubic the surface is light and as close to the truth
  local sh = synth.shapes.wing()
  local path = dir .. "/wing.xyz"
  synth.write_xyz(synth.cloud(sh, { n = 100000, noise = 0.005, seed = 3 }), path)
  local o = { axis = "z", slices = 8, thickness = 0.2, cell = 0.1 }
  local light = pipeline.run(path, o)
  o.skin_tol = 0
  local exact = pipeline.run(path, o)
  local ne, nl = exact.surface:count(), light.surface:count()
  local ee, el = max_radial_error(exact.surface, sh, 100), max_radial_error(light.surface, sh, 100)
  print(("# wing cloud: %d columns exact, %d within %.3g; %.3g and %.3g from the truth"):format(
    ne, nl, light.skin.tol, ee, el))
  T.ok(light.skin.count > 0 and 3 * nl < ne, ("%d columns against %d"):format(nl, ne))
  T.ok(el <= ee + 2 * light.skin.tol, ("%.3g from the truth"):format(el))
end)

T.test("clean up", function() T.ok(os.execute("rm -rf '" .. dir .. "'"), "removed") end)
