-- test_filter_smooth.lua: bs.filter.smooth / reduce / kernel / distance from Lua (issue 17),
-- the strategies' smooth = {tol = t}, `bsfit filter --tol` and `bsfit reconstruct
-- --smooth-tol`. Distances are checked independently of the library's closest points:
-- synth.hausdorff measures the result against a dense polyline of the input (grid search
-- of exact point-segment distances; the polylines cut the tips of a noisy fit's wiggles,
-- so it agrees with the true distance to a few percent only: test_filter_reduce.c checks
-- the reported distance to 1% against brute-force closest points); the box filter of the
-- same deviation is found by this file's own bisection.
local T = require "tap"
local bs = require "bsfit"
local synth = require "synth"
local periodic = require "bsfit.strategy.periodic"
local filter_cli = require "bsfit.cli.filter"
local rc = require "bsfit.cli.reconstruct"

local SRC = (arg and arg[1] or ""):match("^(.*)/tests/lua/[^/]*$")
            or os.getenv("BSFIT_SOURCE_DIR") or "."

local function tmpdir()
  local d = os.tmpname()
  os.remove(d)
  os.execute("mkdir -p '" .. d .. "'")
  return d
end

-- k samples of C as a table of {x, y} (the "truth" polyline of synth.hausdorff)
local function polyline(C, k)
  local S, t = C:sample(k), {}
  for i = 1, #S do t[i] = { S:get(i) } end
  return t
end

local function extent(pts)
  local lo, hi = math.huge, -math.huge
  for _, p in ipairs(pts) do lo = math.min(lo, p[1], p[2]); hi = math.max(hi, p[1], p[2]) end
  return hi - lo
end

local E = 2000 -- samples for the energies compared

-- the box filter (order 1) whose distance to C is dev, by bisection on its half-width
local function box_of_deviation(C, dev)
  local a, b = C:domain()
  local lo, hi = 0, (b - a) / 2
  for _ = 1, 24 do
    local mid = 0.5 * (lo + hi)
    local F = bs.filter.box(C, { delta = mid })
    if bs.filter.distance(F, C, 8) <= dev then lo = mid else hi = mid end
  end
  return bs.filter.box(C, { delta = lo })
end

-- under the sanitizers (BSFIT_SANITIZED, set by CMake) one noise level and one seed of each
-- case: the independent measures below run in Lua, which they slow threefold; the normal
-- build runs them all
local NOISES = T.thinned and { 0.003 } or { 0.001, 0.003, 0.01 }
local SEEDS = T.thinned and 1 or 3

local SHAPES = {
  { "ellipse", synth.sample_smooth(synth.smooth.ellipse, 400, false) },
  { "star", synth.sample_smooth(synth.smooth.star, 400, true) },
  { "airfoil", synth.airfoil(300) },
}

T.test("smooth: noisy sections come back cubic, within tol, smoother than one box pass", function()
  local seed = 1
  for _, shape in ipairs(SHAPES) do
    local name, pts = shape[1], shape[2]
    local size = extent(pts)
    for _, noise in ipairs(NOISES) do
      seed = seed + 1
      local C = periodic.run(synth.noisy(pts, noise * size, seed))
      local tol = 4 * noise * size
      local S, rep = bs.filter.smooth(C, { tol = tol })
      local what = ("%s noise %g"):format(name, noise)
      T.ok(S, what .. ": " .. tostring(rep))
      T.eq(S:degree(), 3, what)
      T.ok(S:is_periodic(), what .. " stays closed")
      T.ok(rep.changed, what .. " changed")
      T.ok(rep.max_deviation <= tol, what .. " reported within tol")
      local d = synth.hausdorff(S, polyline(C, 8000), 4000)
      T.ok(d <= 1.05 * tol, ("%s: distance %g > tol %g"):format(what, d, tol))
      T.near(d, rep.max_deviation, 0.05 * tol, what .. ": the reported distance is the true one")
      local eS, eC = S:bending_energy(E), C:bending_energy(E)
      T.ok(eS < eC, what .. " bending energy drops")
      local B = box_of_deviation(C, rep.max_deviation)
      T.ok(eS < B:bending_energy(E),
           ("%s: energy %g, one box pass of the same deviation %g")
             :format(what, eS, B:bending_energy(E)))
      local n = math.max(8 * (C:count() - 3), 256) -- the samples smooth uses
      T.near(rep.energy_before, C:bending_energy(n), 1e-9 * eC)
    end
  end
end)

T.test("smooth: an already smooth curve with a small tol changes almost nothing", function()
  for i, shape in ipairs(SHAPES) do
    local C = periodic.run(bs.points.new(shape[2]))
    local tol = 1e-4 * extent(shape[2])
    local S, rep = bs.filter.smooth(C, { tol = tol })
    T.ok(S, tostring(rep))
    T.eq(S:degree(), 3)
    T.ok(synth.hausdorff(S, polyline(C, 8000), 4000) <= 1.05 * tol, shape[1])
    local tC, eC = C:total_turning(E), C:bending_energy(E)
    T.near(S:total_turning(E), tC, 1e-3 * tC, shape[1] .. " turning")
    T.near(S:bending_energy(E), eC, 0.05 * eC, shape[1] .. " energy")
    T.ok(i > 0)
  end
end)

T.test("smooth: order and degree as asked; a tolerance nothing can meet changes nothing", function()
  local C = periodic.run(synth.noisy(SHAPES[1][2], 0.01, 7))
  for r = 1, 4 do
    local S, rep = bs.filter.smooth(C, { tol = 0.02, order = r })
    T.eq(rep.order, r)
    T.ok(rep.delta > 0 and rep.max_deviation <= 0.02)
    T.eq(S:degree(), 3)
  end
  local S5, rep5 = bs.filter.smooth(C, { tol = 0.02, degree = 5 })
  T.eq(S5:degree(), 5)
  T.ok(rep5.max_deviation <= 0.02)
  local S0, rep0 = bs.filter.smooth(C, { tol = 1e-12 })
  T.eq(rep0.changed, false)
  T.eq(rep0.order, 0)
  T.eq(S0:degree(), 3)
  T.ok(bs.filter.distance(S0, C) <= 1e-12, "unchanged means unchanged")
end)

T.test("smooth, reduce, kernel: bad input raises with the option's name", function()
  local C = periodic.run(synth.noisy(SHAPES[1][2], 0.01, 8))
  for _, bad in ipairs { 0, -1, 0 / 0, math.huge } do
    T.raises({ match = "'tol'" }, bs.filter.smooth, C, { tol = bad })
  end
  T.raises({ match = "'tol' is required" }, bs.filter.smooth, C, {})
  T.raises({ match = "'order'" }, bs.filter.smooth, C, { tol = 0.1, order = 0 })
  T.raises({ match = "'degree'" }, bs.filter.smooth, C, { tol = 0.1, degree = 0 })
  T.raises({ match = "unknown option" }, bs.filter.smooth, C, { tol = 0.1, width = 2 })
  T.raises({ match = "'tol'" }, bs.filter.reduce, C, { tol = 0 })
  T.raises({ match = "'tol'" }, bs.filter.reduce, C, { tol = 0 / 0 })
  T.raises({ match = "'degree'" }, bs.filter.reduce, C, { degree = 0 })
  T.raises({ match = "'order'" }, bs.filter.kernel, C, { order = 0, delta = 0.01 })
  T.raises({ match = "exactly one" }, bs.filter.kernel, C, { order = 2 })
  T.raises({ match = "exactly one" }, bs.filter.kernel, C, { order = 2, k = 1, delta = 0.1 })
  T.raises({ match = "must be > 0" }, bs.filter.kernel, C, { order = 2, delta = -1 })
  local N = bs.curve.new_nurbs and bs.curve.new_nurbs or nil
  if N then T.raises({ match = "rational" }, bs.filter.smooth, N, { tol = 0.1 }) end
end)

T.test("reduce: an elevated curve comes back; a tight tol adds knots and says which", function()
  local C = periodic.run(synth.noisy(SHAPES[2][2], 0.005, 9))
  local R, rep = bs.filter.reduce(C:elevate(2))
  T.eq(R:degree(), 3)
  T.eq(#rep.knots_added, 0)
  T.ok(rep.max_deviation <= 1e-10, "elevated then reduced: " .. rep.max_deviation)
  T.ok(bs.filter.distance(R, C) <= 1e-10)
  local F = bs.filter.kernel(C, { order = 2, delta = 0.004 })
  T.eq(F:degree(), 5)
  local R2, rep2 = bs.filter.reduce(F, { tol = 1e-5 })
  T.ok(rep2.max_deviation <= 1e-5)
  T.ok(#rep2.knots_added > 0, "knots were needed")
  for _, x in ipairs(rep2.knots_added) do
    local a, b = R2:domain()
    T.ok(x > a and x < b)
  end
  T.fails("ENOCONV", bs.filter.reduce, F, { tol = 1e-13, max_added = 1 })
end)

T.test("strategies: smooth = {tol = t} gives a cubic within t and says what it did", function()
  local P = synth.noisy(SHAPES[3][2], 0.003, 10)
  local C0 = periodic.run(P)
  local C, rep = periodic.run(P, { smooth = { tol = 0.004 } })
  local s = rep.smoothing
  T.eq(C:degree(), 3)
  T.ok(s.changed and s.order >= 1 and s.delta > 0 and s.deviation <= 0.004)
  T.ok(s.bending[2] < s.bending[1])
  T.ok(synth.hausdorff(C, polyline(C0, 8000), 4000) <= 0.004 * 1.05)
  T.raises({ match = "option 'smooth'" }, function() periodic.run(P, { smooth = { tol = -1 } }) end)
  for _, bad in ipairs { { tol = 1, k = 2 }, { tol = 1, order = 0 } } do
    T.raises({ match = "option 'smooth'" }, function() periodic.run(P, { smooth = bad }) end)
  end
end)

T.test("bsfit filter --tol and bsfit reconstruct --smooth-tol", function()
  local d = tmpdir()
  local C = periodic.run(synth.noisy(SHAPES[1][2], 0.01, 11))
  local f = assert(io.open(d .. "/c.json", "w"))
  f:write(C:to_json())
  f:close()
  T.eq(filter_cli.main { d .. "/c.json", "--tol", "0.02", "-o", d .. "/s.json" }, 0)
  local S = bs.curve.read(d .. "/s.json")
  T.eq(S:degree(), 3)
  T.ok(bs.filter.distance(S, C) <= 0.02)
  T.eq(filter_cli.main { d .. "/c.json", "--tol", "0.02", "--order", "2", "--degree", "4",
                         "-o", d .. "/s4.json" }, 0)
  T.eq(bs.curve.read(d .. "/s4.json"):degree(), 4)
  T.eq(filter_cli.main { d .. "/c.json", "--tol", "0" }, 2)
  T.eq(filter_cli.main { d .. "/c.json", "--tol", "0.1", "-k", "2" }, 2)
  T.eq(filter_cli.main { d .. "/c.json", "--order", "2", "-k", "2" }, 2)
  local o = rc.parse { "--smooth-tol", "0.01", "x.csv" }
  T.eq(o.smooth_tol, 0.01)
  T.raises({ match = "smooth%-tol" }, rc.parse, { "--smooth-tol", "-1" })
  local row = rc.section { path = SRC .. "/tests/data/demo/cam.csv", name = "cam", outdir = d,
                           strategy = "periodic", degree = 3, samples = 20, smooth_tol = 0.01,
                           formats = { json = true } }
  T.eq(row.status, "ok", row.error)
  local cam = bs.curve.read(d .. "/cam.json")
  T.eq(cam:degree(), 3)
  os.execute("rm -rf '" .. d .. "'")
end)

-- a clamped bicubic height field z = f(x, y) on Greville points, control heights noisy
local function noisy_surface(n, noise, seed)
  local _, gauss = synth.rng(seed)
  local U = { 0, 0, 0, 0 }
  for i = 1, n - 4 do U[#U + 1] = i / (n - 3) end
  for _ = 1, 4 do U[#U + 1] = 1 end
  local g = {}
  for i = 1, n do g[i] = (U[i + 1] + U[i + 2] + U[i + 3]) / 3 end
  local rows = {}
  for i = 1, n do
    rows[i] = {}
    for j = 1, n do
      local x, y = g[i], g[j]
      rows[i][j] = { x, y, 0.3 * math.sin(3 * x) * math.cos(2 * y) + noise * gauss() }
    end
  end
  return bs.surface.new { degree_u = 3, degree_v = 3, knots_u = U, knots_v = U,
                          control_points = rows }
end

-- the distance from each of k x k points of A to a dense grid of B's points (brute force)
local function surface_distance(A, B, k, dense)
  local Bp = {}
  for i = 0, dense do
    for j = 0, dense do Bp[#Bp + 1] = { B:eval(i / dense, j / dense) } end
  end
  local worst = 0
  for i = 0, k do
    for j = 0, k do
      local x, y, z = A:eval(i / k, j / k)
      local best = math.huge
      for _, p in ipairs(Bp) do
        local d = (p[1] - x) ^ 2 + (p[2] - y) ^ 2 + (p[3] - z) ^ 2
        if d < best then best = d end
      end
      worst = math.max(worst, math.sqrt(best))
    end
  end
  return worst
end

T.test("smooth: a noisy surface comes back bicubic, within tol, less thin-plate energy", function()
  for seed = 1, SEEDS do
    local noise = 0.002 * seed
    local S = noisy_surface(14, noise, seed)
    -- near the edges the end rule (the surface extended as constant) moves the filter
    -- by about delta times the slope: the tolerance leaves room for it
    local tol = 10 * noise
    local R, rep = bs.filter.smooth(S, { tol = tol })
    T.ok(R, tostring(rep))
    local pu, pv = R:degree()
    T.eq(pu, 3)
    T.eq(pv, 3)
    T.ok(rep.changed and rep.order >= 1 and rep.delta > 0)
    T.ok(rep.max_deviation <= tol)
    T.ok(rep.energy_after < rep.energy_before, "thin-plate energy drops (interior)")
    local a, b, c, d = R:domain()
    T.eq(a, 0.0)
    T.eq(b, 1.0)
    T.eq(c, 0.0)
    T.eq(d, 1.0)
    -- every probed point of the result within tol of the input, up to the dense grid's spacing
    T.ok(surface_distance(R, S, 12, 120) <= tol + 0.01 * 0.5, "within tol")
  end
  local S = noisy_surface(10, 0.01, 4)
  local R0, rep0 = bs.filter.smooth(S, { tol = 1e-9 })
  T.eq(rep0.changed, false)
  T.eq(select(2, R0:degree()), 3)
  T.raises({ match = "'tol'" }, bs.filter.smooth, S, { tol = -1 })
  T.raises({ match = "'order'" }, bs.filter.smooth, S, { tol = 1, order = 0 })
end)

T.test("smooth: open sections keep their domain and stay within tol", function()
  for seed = 1, SEEDS do
    local pts = {}
    for i = 0, 299 do
      local t = 1.5 * math.pi * i / 299
      pts[#pts + 1] = { 2 * math.cos(t), math.sin(t) }
    end
    local C = periodic.run(synth.noisy(pts, 0.004 * seed, 20 + seed), { closed = false })
    T.ok(not C:is_periodic())
    local tol = 4 * 0.004 * seed
    local S, rep = bs.filter.smooth(C, { tol = tol })
    T.ok(S, tostring(rep))
    T.eq(S:degree(), 3)
    T.ok(not S:is_periodic())
    local a, b = C:domain()
    local c, d = S:domain()
    T.eq(c, a)
    T.eq(d, b)
    T.ok(rep.max_deviation <= tol)
    T.ok(bs.filter.distance(S, C, 32) <= 1.01 * tol, "the true distance, denser")
    T.ok(not rep.changed or S:bending_energy(E) < C:bending_energy(E))
  end
end)

-- the largest |A(u, v) - B(u, v)| on a k x k grid (dense sampling, independent of the bound)
local function sampled_difference(A, B, k)
  local worst = 0
  for i = 0, k do
    for j = 0, k do
      local x, y, z = A:eval(i / k, j / k)
      local p, q, r = B:eval(i / k, j / k)
      worst = math.max(worst, math.sqrt((x - p) ^ 2 + (y - q) ^ 2 + (z - r) ^ 2))
    end
  end
  return worst
end

T.test("reduce: surfaces, raised and lowered again, and within a tolerance", function()
  for seed = 1, SEEDS do
    local S = noisy_surface(9 + seed, 0.01 * seed, 10 + seed)
    -- degree 4 on the same break points holds S exactly; back to 3 it is S again
    local S4, r4 = bs.filter.reduce(S, { degree = 4 })
    T.eq(select(1, S4:degree()), 4)
    T.ok(sampled_difference(S4, S, 40) <= 1e-12, "raised")
    local S3, r3 = bs.filter.reduce(S4, { degree = { 3, 3 }, tol = 1e-9 })
    T.ok(S3, tostring(r3))
    T.eq(r3.knots_added, 0)
    local P, Q = S3:control_points(), S:control_points() -- Points, row-major over (i, j)
    T.eq(#P, #Q)
    for i = 1, #P do
      local a, b = { P:get(i) }, { Q:get(i) }
      for k = 1, 3 do T.near(a[k], b[k], 1e-12) end
    end
    -- lower degrees within tol: the bound holds against sampling and meets tol
    local tol = 0.002
    local R, rep = bs.filter.reduce(S, { degree = { 2, 1 }, tol = tol })
    T.ok(R, tostring(rep))
    local pu, pv = R:degree()
    T.eq(pu, 2)
    T.eq(pv, 1)
    T.ok(rep.bound <= tol and rep.max_deviation == rep.bound)
    T.ok(sampled_difference(R, S, 60) <= rep.bound, "the bound is an upper bound")
    T.ok(rep.knots_added > 0, "knots were needed")
    T.ok(r4.bound <= 1e-10, "the bound of an exact result: its rounding slack only")
  end
  local S = noisy_surface(8, 0.01, 1)
  T.raises({ match = "'degree'" }, bs.filter.reduce, S, { degree = { 3 } })
  T.raises({ match = "'degree'" }, bs.filter.reduce, S, { degree = 0 })
  T.raises({ match = "'tol'" }, bs.filter.reduce, S, { tol = 0 })
  local R, msg, code = bs.filter.reduce(S, { degree = 1, tol = 1e-12, max_added = 4 })
  T.eq(R, nil)
  T.eq(code, "ENOCONV")
  T.ok(msg:match("not reached"), msg)
end)
