-- test_skin_tol.lua: the tolerance skin on dense mesh loops. A vase meshed with 1000 x 500
-- quads cut by a few planes gives loops of 2000+ points; auto fits them with a C0 knot at
-- every facet (3000-5000 control points each, their parametrisation jumping from piece to
-- piece). The skin within the mesh's tessellation error used to fall back to the exact
-- surface (5364 columns for 8 slices): its check compared the cubics with the sections at
-- equal parameters. Now it must be light, and within its tolerance of every section as a
-- distance measured here independently: each section sampled at its knots and 4000 points,
-- the surface's iso-curve through it at 4000 points, each point's nearest sample of the
-- other curve (by angle about the axis: the vase is round) refined by golden sections.
local T = require "tap"
local bs = require "bsfit"
local synth = require "scan_synth"
local pipeline = require "bsfit.scan.pipeline"

local function dist(x1, y1, z1, x2, y2, z2)
  return math.sqrt((x1 - x2) ^ 2 + (y1 - y2) ^ 2 + (z1 - z2) ^ 2)
end

local BUCKETS = 720

-- n samples of the closed curve f(x), x in [0, 1), bucketed by angle about the z axis.
local function sampled(f, n)
  local smp = { f = f, n = n, b = {} }
  for i = 0, BUCKETS - 1 do smp.b[i] = {} end
  for i = 0, n - 1 do
    local x, y, z = f(i / n)
    local k = math.floor((math.atan(y, x) / (2 * math.pi) + 0.5) * BUCKETS) % BUCKETS
    table.insert(smp.b[k], { i / n, x, y, z })
  end
  return smp
end

-- The distance from (x, y, z) to the sampled curve: the nearest sample of the point's
-- bucket and its neighbours, refined by golden sections within a sample step.
local function distance_to(smp, x, y, z)
  local k = math.floor((math.atan(y, x) / (2 * math.pi) + 0.5) * BUCKETS) % BUCKETS
  local best, at = math.huge, 0
  for d = -2, 2 do
    for _, s in ipairs(smp.b[(k + d) % BUCKETS]) do
      local e = dist(x, y, z, s[2], s[3], s[4])
      if e < best then best, at = e, s[1] end
    end
  end
  local function g(u) return dist(x, y, z, smp.f(u % 1)) end
  local lo, hi, r = at - 1 / smp.n, at + 1 / smp.n, (math.sqrt(5) - 1) / 2
  for _ = 1, 50 do
    local c, e = hi - r * (hi - lo), lo + r * (hi - lo)
    if g(c) < g(e) then hi = e else lo = c end
  end
  return math.min(best, g((lo + hi) / 2))
end

-- The Hausdorff distance between section C and S(., v), both ways.
local function hausdorff(C, S, v)
  local a, b = C:domain()
  local function fc(x) return C:eval(a + (b - a) * x) end
  local function fs(x) return S:eval(x, v) end
  local sc, ss, worst = sampled(fc, 4000), sampled(fs, 4000), 0
  local xs = {}
  for i = 0, 3999 do xs[#xs + 1] = (i + 0.5) / 4000 end
  for _, t in ipairs(C:knots()) do
    if t >= a and t < b then xs[#xs + 1] = (t - a) / (b - a) end
  end
  for _, x in ipairs(xs) do worst = math.max(worst, distance_to(ss, fc(x))) end
  for i = 0, 3999 do worst = math.max(worst, distance_to(sc, fs((i + 0.5) / 4000))) end
  return worst
end

local dir = os.tmpname()
os.remove(dir)
os.execute("mkdir -p '" .. dir .. "'")

T.test("dense mesh loops of a vase skin light, within the tolerance as a distance", function()
  local path = dir .. "/vase.ply"
  synth.write_ply(synth.mesh(synth.shapes.vase(), { around = 1000, rings = 500 }), path,
                  "binary_little_endian")
  for _, run in ipairs { { slices = 8 }, { slices = 8, skin_tol = 3e-5 } } do
    local res = pipeline.run(path, { axis = "z", slices = run.slices, skin_tol = run.skin_tol })
    local rep = assert(res.skin, res.surface_message)
    local heavy = 0
    for _, C in ipairs(rep.sections) do heavy = math.max(heavy, #C:control_points()) end
    T.ok(heavy > 2000, ("dense sections: %d control points"):format(heavy))
    T.ok(rep.count > 0 and rep.count < 200, ("light: %d columns (tol %.3g)"):format(
      (res.surface:count()), rep.tol))
    T.ok(rep.max_deviation <= rep.tol, ("max_deviation %.3g <= tol %.3g"):format(
      rep.max_deviation, rep.tol))
    local worst = 0
    for k, C in ipairs(rep.sections) do
      worst = math.max(worst, hausdorff(C, res.surface, rep.v_params[k]))
    end
    print(("# %d slices: tol %.3g, %d columns, max_deviation %.4g, measured %.4g"):format(
      run.slices, rep.tol, (res.surface:count()), rep.max_deviation, worst))
    T.ok(worst <= rep.max_deviation * (1 + 1e-6), ("measured %.4g <= reported %.4g"):format(
      worst, rep.max_deviation))
    T.ok(rep.max_deviation - worst <= 0.05 * rep.tol, "the report is the distance, not a bound")
  end
end)

T.test("clean up", function()
  os.execute("rm -rf '" .. dir .. "'")
  T.ok(true)
end)
