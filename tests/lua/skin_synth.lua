-- skin_synth.lua
-- Stacks of closed sections with corners for the skinning tests: a 2D profile (prisms,
-- rounded boxes whose corner radius changes along the stack down to sharp corners,
-- extruded letters, ellipses) swept along z with a twist and a taper; each section is
-- sampled from a random start point in a random direction and fitted by the auto strategy
-- (corners become C0 knots, so the sections' knot vectors all differ), mapped to its
-- height, and made polynomial (bs.filter.reduce) where auto wrote exact arcs. Every stack
-- knows its true surface: `stack.distance(x, y, z)` is the distance from (x, y) to the
-- true section at height z (an upper bound of the distance to the surface).

local bs = require "bsfit"
local auto = require "bsfit.strategy.auto"
local steps = require "bsfit.scan.steps"

local M = {}

-- {======================================================================
-- Profiles: point(t) for t in [0, 1) and distance(x, y), at a parameter s in [0, 1]
-- along the stack (the rounded box's radius changes with it)
-- =======================================================================

local function seg_dist(x, y, a, b)
  local dx, dy = b[1] - a[1], b[2] - a[2]
  local f = math.max(0, math.min(1, ((x - a[1]) * dx + (y - a[2]) * dy) / (dx * dx + dy * dy)))
  return math.sqrt((a[1] + f * dx - x) ^ 2 + (a[2] + f * dy - y) ^ 2)
end

-- A closed polygon, parametrised by arc length.
local function polygon(V)
  local acc, L = { 0 }, 0
  for i = 1, #V do
    local a, b = V[i], V[i % #V + 1]
    L = L + math.sqrt((b[1] - a[1]) ^ 2 + (b[2] - a[2]) ^ 2)
    acc[i + 1] = L
  end
  local pr = {}
  function pr.point(t)
    local s = (t % 1) * L
    for i = 1, #V do
      if s <= acc[i + 1] then
        local f, a, b = (s - acc[i]) / (acc[i + 1] - acc[i]), V[i], V[i % #V + 1]
        return a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])
      end
    end
    return V[1][1], V[1][2]
  end
  function pr.distance(x, y)
    local best = math.huge
    for i = 1, #V do best = math.min(best, seg_dist(x, y, V[i], V[i % #V + 1])) end
    return best
  end
  return pr
end

-- A 2hx x 2hy rectangle with corners rounded to radius r (0: sharp), by arc length.
local function rounded_box(hx, hy, r)
  if r <= 0 then return polygon { { hx, -hy }, { hx, hy }, { -hx, hy }, { -hx, -hy } } end
  local ax, ay = hx - r, hy - r
  local parts = { -- {kind, data, length}: sides and quarter arcs, counter-clockwise
    { "line", { hx, -ay }, { hx, ay } }, { "arc", { ax, ay }, 0 },
    { "line", { ax, hy }, { -ax, hy } }, { "arc", { -ax, ay }, math.pi / 2 },
    { "line", { -hx, ay }, { -hx, -ay } }, { "arc", { -ax, -ay }, math.pi },
    { "line", { -ax, -hy }, { ax, -hy } }, { "arc", { ax, -ay }, 3 * math.pi / 2 } }
  local L = 0
  for _, q in ipairs(parts) do
    q.len = q[1] == "line" and math.sqrt((q[3][1] - q[2][1]) ^ 2 + (q[3][2] - q[2][2]) ^ 2)
      or r * math.pi / 2
    L = L + q.len
  end
  local pr = {}
  function pr.point(t)
    local s = (t % 1) * L
    for _, q in ipairs(parts) do
      if s <= q.len then
        local f = s / q.len
        if q[1] == "line" then
          return q[2][1] + f * (q[3][1] - q[2][1]), q[2][2] + f * (q[3][2] - q[2][2])
        end
        local a = q[3] + f * math.pi / 2
        return q[2][1] + r * math.cos(a), q[2][2] + r * math.sin(a)
      end
      s = s - q.len
    end
    return hx, -ay
  end
  function pr.distance(x, y) -- the rounded box's exact distance
    local qx, qy = math.abs(x) - ax, math.abs(y) - ay
    local out = math.sqrt(math.max(qx, 0) ^ 2 + math.max(qy, 0) ^ 2)
    return math.abs(out + math.min(math.max(qx, qy), 0) - r)
  end
  return pr
end

local function ellipse(a, b)
  local pr = {}
  function pr.point(t) return a * math.cos(2 * math.pi * t), b * math.sin(2 * math.pi * t) end
  function pr.distance(x, y) -- the nearest of 512 samples, refined by golden sections
    local n, bi, best = 512, 0, math.huge
    for i = 0, n - 1 do
      local qx, qy = pr.point(i / n)
      local d = (qx - x) ^ 2 + (qy - y) ^ 2
      if d < best then bi, best = i, d end
    end
    local lo, hi, g = (bi - 1) / n, (bi + 1) / n, (math.sqrt(5) - 1) / 2
    local function f(t) local qx, qy = pr.point(t); return (qx - x) ^ 2 + (qy - y) ^ 2 end
    for _ = 1, 60 do
      local a, b = hi - g * (hi - lo), lo + g * (hi - lo)
      if f(a) < f(b) then hi = b else lo = a end
    end
    return math.sqrt(math.min(best, f((lo + hi) / 2)))
  end
  return pr
end

-- Profile families: make(rng) returns profile(s), s in [0, 1] along the stack.
M.families = {
  prism = function(r)
    local n = r.int(3, 8)
    local V = {}
    for i = 0, n - 1 do V[#V + 1] = { 3 * math.cos(2 * math.pi * i / n), 3 * math.sin(2 * math.pi * i / n) } end
    local pr = polygon(V)
    return function() return pr end
  end,
  rounded_box = function(r) -- sharp at one end, corner radius up to 1.2 at the other
    local hx, hy, rmax = r.range(2.5, 4), r.range(1.5, 2.5), r.range(0.4, 1.2)
    local sharp_first = r.uniform() < 0.5
    return function(s) return rounded_box(hx, hy, rmax * (sharp_first and s or 1 - s)) end
  end,
  letter = function(r)
    local shapes = {
      { { 0, 0 }, { 4, 0 }, { 4, 1 }, { 1, 1 }, { 1, 5 }, { 0, 5 } },                             -- L
      { { -3, 4 }, { 3, 4 }, { 3, 3 }, { 0.6, 3 }, { 0.6, 0 }, { -0.6, 0 }, { -0.6, 3 }, { -3, 3 } }, -- T
      { { 0, 0 }, { 3, 0 }, { 3, 1 }, { 1, 1 }, { 1, 2 }, { 2.5, 2 }, { 2.5, 3 }, { 1, 3 },        -- E
        { 1, 4 }, { 3, 4 }, { 3, 5 }, { 0, 5 } },
    }
    local pr = polygon(shapes[r.int(1, #shapes)])
    return function() return pr end
  end,
  ellipse = function(r)
    local a, b = r.range(2, 4), r.range(1.5, 3)
    return function(s) return ellipse(a * (1 + 0.2 * math.sin(3 * s)), b) end
  end,
}
M.family_names = { "prism", "rounded_box", "letter", "ellipse" }

-- }======================================================================

-- {======================================================================
-- Stacks
-- =======================================================================

-- scan_synth's generator, with uniform numbers in a range and integers in [a, b]
function M.rng(seed)
  local r = require("scan_synth").rng(seed)
  function r.range(a, b) return a + (b - a) * r.uniform() end
  function r.int(a, b) return math.min(b, a + math.floor((b - a + 1) * r.uniform())) end
  return r
end

-- The section of prof at height z (twist angle, scale), as a polynomial 3D curve.
local function section(prof, m, start, reverse, z, angle, scale)
  local P = {}
  for i = 0, m - 1 do
    P[i + 1] = { prof.point(start + (reverse and -i or i) / m) }
  end
  local C, rep = auto.run(bs.points.new(P), { closed = true })
  assert(C and rep.closed, "auto gave no closed curve")
  -- the scan pipeline's map to 3D, with the plane's axes turned and scaled
  local ca, sa = math.cos(angle), math.sin(angle)
  local C3 = steps.to3d(C, { origin = { 0, 0, z }, u = { scale * ca, scale * sa, 0 },
                             v = { -scale * sa, scale * ca, 0 } })
  if C3:is_rational() then C3 = assert(bs.filter.reduce(C3, { degree = 3, tol = 1e-5 })) end
  return C3
end

-- A random stack: {sections, family, K, distance(x, y, z), size}. o.family forces one.
function M.stack(r, o)
  o = o or {}
  local fam = o.family or M.family_names[r.int(1, #M.family_names)]
  local profile = M.families[fam](r)
  local K = o.K or r.int(3, 40)
  local height = r.range(4, 12)
  local twist = r.range(-0.5, 0.5) / height  -- radians per unit of height
  local taper = r.range(-0.3, 0.3) / height  -- relative scale change per unit
  local st = { family = fam, K = K, sections = {}, size = 10, z0 = 0, z1 = height }
  local function frame(z) return twist * z, 1 + taper * z end
  for k = 1, K do
    local z = height * (k - 1) / (K - 1)
    local angle, scale = frame(z)
    st.sections[k] = section(profile(z / height), r.int(60, 200), r.uniform(), r.uniform() < 0.4,
                             z, angle, scale)
  end
  function st.distance(x, y, z)
    local angle, scale = frame(z)
    local ca, sa = math.cos(-angle), math.sin(-angle)
    local px, py = (ca * x - sa * y) / scale, (sa * x + ca * y) / scale
    return profile(math.max(0, math.min(1, z / height))).distance(px, py) * scale
  end
  return st
end

-- }======================================================================

return M
