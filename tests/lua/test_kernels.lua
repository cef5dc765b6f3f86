-- test_kernels.lua: bs.weights.* (src/lua/lweights.c) and bs.geom.* (src/lua/lgeom.c)
-- against geometry: regular polygons (R = s / (2 sin(pi/m)), interior angle 180 (m-2)/m),
-- a rounded square (corners and straight runs weigh most), a star (2 inflections per
-- spike), noise of a known sigma, the corners of a square and of none of a circle, the
-- demo set, and the error contract (point numbers count from 1).
local T = require "tap"
local bs = require "bsfit"

local pi, cos, sin, sqrt = math.pi, math.cos, math.sin, math.sqrt

local function polygon(m, R, cx, cy, phase)
  local t = {}
  for k = 0, m - 1 do
    local a = phase + 2 * pi * k / m
    t[#t + 1] = {cx + R * cos(a), cy + R * sin(a)}
  end
  return t
end

-- every value of Vector v near want (relative tolerance tol)
local function all_near(v, want, tol, msg)
  for i = 1, #v do T.near(v:get(i), want, tol, (msg or "value") .. " " .. i) end
end

-- a star with s spikes: 2s vertices at radii 1 and 0.4, each side cut in `sub`
local function star(s, sub)
  local t, nv = {}, 2 * s
  for v = 0, nv - 1 do
    local a0, a1 = 2 * pi * v / nv, 2 * pi * (v + 1) / nv
    local r0, r1 = (v % 2 == 1) and 0.4 or 1, (v % 2 == 1) and 1 or 0.4
    local x0, y0, x1, y1 = r0 * cos(a0), r0 * sin(a0), r1 * cos(a1), r1 * sin(a1)
    for j = 0, sub - 1 do
      local f = j / sub
      t[#t + 1] = {x0 + f * (x1 - x0), y0 + f * (y1 - y0)}
    end
  end
  return t
end

-- the square [0,10]^2 with corners rounded by radius 1: per side the points 1..9 along
-- it (1 and 9 are transitions to the arcs), per corner the arc's midpoint; kind[i] is
-- "straight", "transition" or "arc"
local function rounded_square()
  local O = {{0, 0}, {10, 0}, {10, 10}, {0, 10}}
  local D = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}}
  local t, kind = {}, {}
  for c = 1, 4 do
    local d = c % 4 + 1
    for j = 1, 9 do
      t[#t + 1] = {O[c][1] + j * D[c][1], O[c][2] + j * D[c][2]}
      kind[#t] = (j == 1 or j == 9) and "transition" or "straight"
    end
    -- arc centre: one unit inside the corner along both sides
    local cx, cy = O[d][1] - D[c][1] + D[d][1], O[d][2] - D[c][2] + D[d][2]
    local mx, my = -D[c][1] + D[d][1], -D[c][2] + D[d][2]
    t[#t + 1] = {cx - mx / sqrt(2), cy - my / sqrt(2)}
    kind[#t] = "arc"
  end
  return t, kind
end

T.test("regular polygons: radii R, weights 1, angles 180(m-2)/m, no inflection", function()
  for _, m in ipairs{3, 5, 8, 13, 40} do
    local P = bs.points.new(polygon(m, 2.5, 1, -3, 0.4))
    local R = 2 * 2.5 * sin(pi / m) / (2 * sin(pi / m))
    local r = bs.geom.circumradius(P, {closed = true})
    T.eq(#r, m)
    all_near(r, R, 1e-12, "radius")
    all_near(bs.geom.circumradius(P, {closed = true, centered = false}), R, 1e-12, "paper radius")
    all_near(bs.weights.circumradius(P, {closed = true}), 1, 1e-12, "weight")
    all_near(bs.geom.angles(P, {closed = true}), 180 * (m - 2) / m, 1e-11, "angle")
    all_near(bs.weights.turning(P, {closed = true}), 2, 1e-12, "turning weight")
    all_near(bs.weights.spacing(P, {closed = true}), 1, 1e-12, "spacing weight")
    T.eq(bs.geom.inflections(P, {closed = true}), 0)
  end
end)

T.test("rounded square: corners and straight runs get w_max, transitions less", function()
  local pts, kind = rounded_square()
  local r = bs.geom.circumradius(pts, {closed = true})
  local w = bs.weights.circumradius(pts, {closed = true})
  local wmax = w:max()
  local rt = r:get(1)
  -- 4 radii 1 (arc midpoints) and 8 radii rt: r_max = mean + std (population)
  local rmax = 1 + (2 / 3 + sqrt(2) / 3) * (rt - 1)
  T.near(wmax, rmax, 1e-12, "w_max = r_max / 1")
  for i = 1, #pts do
    if kind[i] == "straight" then
      T.eq(r:get(i), math.huge, "straight radius")
      T.near(w:get(i), wmax, 1e-12, "straight weight")
    elseif kind[i] == "arc" then
      T.near(r:get(i), 1, 1e-12, "arc radius")
      T.near(w:get(i), wmax, 1e-12, "arc weight")
    else
      T.near(w:get(i), rmax / rt, 1e-12, "transition weight")
      T.ok(w:get(i) > 1 and w:get(i) < wmax, "transition weight below w_max")
    end
  end
end)

T.test("star: two inflections per spike, collinear points skipped, also in 3D", function()
  for sub = 1, 3 do
    local pts = star(5, sub)
    T.eq(bs.geom.inflections(pts, {closed = true}), 10, "2D star, sub " .. sub)
    local p3 = {}
    -- an isometry onto a tilted plane: (x, y) -> x e1 + y e2, e1, e2 orthonormal
    for i, p in ipairs(pts) do
      p3[i] = {p[1] * 2 / 3 - p[2] / 3, p[1] / 3 - p[2] * 2 / 3, (p[1] + p[2]) * 2 / 3}
    end
    T.eq(bs.geom.inflections(bs.points.new(p3), {closed = true}), 10, "3D star, sub " .. sub)
  end
  T.eq(bs.geom.inflections(star(3, 1), {closed = true}), 6)
end)

T.test("open data: a circular arc has radius R everywhere, the ends copy neighbours", function()
  local pts = {}
  for k = 0, 20 do
    local a = 0.1 + 1.3 * k / 20 + 0.02 * sin(7 * k) -- uneven spacing
    pts[#pts + 1] = {4 * cos(a), 4 * sin(a)}
  end
  all_near(bs.geom.circumradius(pts, {closed = false}), 4, 1e-12, "arc radius")
  local ang = bs.geom.angles(pts, {closed = false})
  T.eq(ang:get(1), ang:get(2))
  T.eq(ang:get(-1), ang:get(-2))
  -- y = sin x on [0.3, 3 pi - 0.3]: curvature changes sign at pi and 2 pi
  local wave = {}
  for k = 0, 60 do
    local x = 0.3 + (3 * pi - 0.6) * k / 60
    wave[#wave + 1] = {x, sin(x)}
  end
  T.eq(bs.geom.inflections(wave, {closed = false}), 2)
end)

T.test("the paper's triple (Q_k, Q_k+1, Q_k+2) is the centred triple of Q_k+1", function()
  local pts = {{0, 0}, {3, 0.5}, {5, 2}, {4, 5}, {1, 4}, {-1, 2}}
  local rc = bs.geom.circumradius(pts, {closed = true, centered = true})
  local rp = bs.geom.circumradius(pts, {closed = true, centered = false})
  for k = 1, #pts do T.eq(rp:get(k), rc:get(k % #pts + 1)) end
  -- the triangle (0,0), (3,0.5), (5,2): R = abc / (4 area), by hand
  local a, b, c = sqrt(9.25), sqrt(6.25), sqrt(29)
  local area = math.abs(3 * 2 - 0.5 * 5) / 2
  T.near(rc:get(2), a * b * c / (4 * area), 1e-13)
end)

T.test("turning and spacing weights by hand", function()
  -- square cut in 3 per side: turns 90 at corners, 0 elsewhere; mean 360/12 = 30
  local sq = {}
  for _, c in ipairs{{0, 0, 1, 0}, {3, 0, 0, 1}, {3, 3, -1, 0}, {0, 3, 0, -1}} do
    for j = 0, 2 do sq[#sq + 1] = {c[1] + j * c[3], c[2] + j * c[4]} end
  end
  local w = bs.weights.turning(sq, {closed = true})
  for i = 1, 12 do T.near(w:get(i), (i % 3 == 1) and 4 or 1, 1e-12, "turning " .. i) end
  -- spacing: chords 1,1,1,1,4,4,4 -> local spacings 2.5,1,1,1,2.5,4,4, mean 16/7
  local cl = {{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}, {4, 4}, {0, 4}}
  local s = bs.weights.spacing(cl, {closed = true})
  for i, want in ipairs{2.5, 1, 1, 1, 2.5, 4, 4} do
    T.near(s:get(i), 7 * want / 16, 1e-14, "spacing " .. i)
  end
  -- open: the ends' one chord stands for both
  s = bs.weights.spacing({{0, 0}, {1, 0}, {3, 0}}, {closed = false})
  T.near(s:get(1), 2 / 3, 1e-14); T.near(s:get(2), 1, 1e-14); T.near(s:get(3), 4 / 3, 1e-14)
end)

T.test("the demo set: one finite weight >= 1 per point for every rule", function()
  local dir = ((arg and arg[1] or ""):match("^(.*)[/\\]") or ".") .. "/../data/demo/"
  for _, name in ipairs{"cam", "airfoil", "bracket", "noisy_blob", "knob_weighted"} do
    local P = assert(bs.points.read(dir .. name .. ".csv"))
    T.ok(#P >= 40 and #P <= 400, name .. " size")
    for _, rule in ipairs{"circumradius", "turning"} do
      local w = bs.weights[rule](P, {closed = true})
      T.eq(#w, #P, name .. " " .. rule .. " count")
      for i = 1, #w do
        local x = w:get(i)
        T.ok(x >= 1 and x < math.huge, name .. " " .. rule .. " weight " .. i)
      end
    end
    local inf = bs.geom.inflections(P, {closed = true})
    T.ok(inf % 2 == 0 and inf < #P, name .. " inflections even and below m")
  end
end)

-- the pattern of `bad argument #n to 'fname' (msg)`; msg is a Lua pattern
local function argerr(n, fname, msg)
  return {match = "^bad argument #" .. n .. " to '[%w_.]*" .. fname .. "' %(" .. msg .. "%)$"}
end

T.test("misuse raises: too few points, bad dim, NaN, bad options, not points", function()
  T.raises(argerr(1, "circumradius", "m = 2 points, at least 3 needed"),
           function() return bs.weights.circumradius({{0, 0}, {1, 1}}, {closed = true}) end)
  T.raises(argerr(1, "angles", "dim must be 2 or 3, got 4"),
           function() return bs.geom.angles(bs.points.new(5, 4), {closed = true}) end)
  T.raises(argerr(1, "inflections", "point 2 has a non%-finite coordinate"),
           function() return bs.geom.inflections({{0, 0}, {0 / 0, 1}, {2, 0}}) end)
  T.raises(argerr(1, "spacing", "point 3 has a non%-finite coordinate"),
           function() return bs.weights.spacing({{0, 0}, {1, 1}, {math.huge, 0}}) end)
  T.raises(argerr(2, "circumradius", "unknown option 'close'"),
           function() return bs.geom.circumradius({{0, 0}, {1, 1}, {2, 0}}, {close = true}) end)
  T.raises(argerr(2, "turning", "field 'closed' must be a boolean"),
           function() return bs.weights.turning({{0, 0}, {1, 1}, {2, 0}}, {closed = 1}) end)
  T.raises(argerr(1, "circumradius", "bsfit.Points expected, got number"),
           function() return bs.weights.circumradius(42) end)
end)

T.test("defaults: closed = true, centered = true; 'centered' only where it applies", function()
  local pts = {{0, 0}, {4, 0}, {5, 3}, {2, 5}, {-1, 3}}
  local a = bs.geom.circumradius(pts)
  local b = bs.geom.circumradius(pts, {closed = true, centered = true})
  for i = 1, #pts do T.eq(a:get(i), b:get(i)) end
  a, b = bs.geom.angles(pts), bs.geom.angles(pts, {closed = true})
  for i = 1, #pts do T.eq(a:get(i), b:get(i)) end
  T.eq(bs.geom.inflections(star(4, 1)), 8)
  T.raises(argerr(2, "angles", "unknown option 'centered'"),
           function() return bs.geom.angles(pts, {centered = true}) end)
  T.raises(argerr(2, "spacing", "table expected, got string"),
           function() return bs.weights.spacing(pts, "closed") end)
end)

T.test("uniform: ones, from points or a count", function()
  local w = bs.weights.uniform(bs.points.new(polygon(7, 1, 0, 0, 0)))
  T.eq(#w, 7)
  all_near(w, 1, 0)
  T.eq(#bs.weights.uniform(3), 3)
  T.eq(#bs.weights.uniform({{0, 0}, {1, 1}}), 2)
  T.eq(#bs.weights.uniform(0), 0)
  T.raises({match = "^bad argument #1 to '[%w_.]*uniform' %(count %-1 out of range"},
           function() return bs.weights.uniform(-1) end)
end)

T.test("untrusted: the weights below trust x median, 1-based; bad weights are data", function()
  -- the rule written out in Lua (sorted copy, element #w // 2 + 1) on many random sets
  local rng = 7
  local function uniform() rng = (rng * 1103515245 + 12345) % 2147483648; return rng / 2147483648 end
  for trial = 1, 300 do
    local m, w = 1 + math.floor(uniform() * 300), {}
    for i = 1, m do
      local x = uniform()
      w[i] = trial % 3 == 0 and (x < 0.03 and 1e-3 or 1) or trial % 3 == 1 and 10 ^ (-5 * x)
             or 1 + math.floor(3 * x)
    end
    local trust = ({ 0, 0.1, 0.5 })[trial % 3 + 1]
    local sorted = { table.unpack(w) }
    table.sort(sorted)
    local cut, want = trust * sorted[m // 2 + 1], {}
    for i = 1, m do if w[i] < cut then want[#want + 1] = i end end
    local got = bs.weights.untrusted(trial % 2 == 0 and w or bs.vector.new(w), trust)
    T.eq(#got, #want, "trial " .. trial .. ": how many")
    for k = 1, #want do T.eq(got[k], want[k], "trial " .. trial .. ": index") end
  end
  T.eq(#bs.weights.untrusted({ 1, 1e-3, 1, 1 }), 1)
  T.eq(bs.weights.untrusted({ 1, 1e-3, 1, 1 })[1], 2)
  local none, msg, code = bs.weights.untrusted({ 1, 2, -1 })
  T.eq(none, nil)
  T.eq(msg, "weight 3 is -1 (must be positive and finite)") -- the words of the misuse check
  T.eq(code, "EWEIGHT")
  T.eq(select(2, bs.weights.untrusted({ 0 / 0 })):match("^weight 1 is"), "weight 1 is")
  T.raises(argerr(2, "untrusted", "trust must be in %[0, 1%)"),
           function() return bs.weights.untrusted({ 1, 2 }, 1) end)
end)

T.test("defaults of the weighting rules: closed = true", function()
  local pts = {{0, 0}, {4, 0}, {5, 3}, {2, 5}, {-1, 3}}
  for _, rule in ipairs{"circumradius", "turning", "spacing"} do
    local a, b = bs.weights[rule](pts), bs.weights[rule](pts, {closed = true})
    for i = 1, #pts do T.eq(a:get(i), b:get(i), rule .. " " .. i) end
  end
  -- open data differ at the ends: the spacing of an end has one chord
  T.ok(bs.weights.spacing(pts):get(1) ~= bs.weights.spacing(pts, {closed = false}):get(1))
  T.raises(argerr(2, "turning", "unknown option 'centered'"),
           function() return bs.weights.turning(pts, {centered = false}) end)
end)

-- Box-Muller normal deviates from Lua's seeded generator (deterministic for a seed)
local function gauss()
  local u1, u2 = math.random(), math.random()
  return sqrt(-2 * math.log(1 - u1)) * cos(2 * pi * u2)
end

-- m points on a circle of radius R, each moved along the normal by sigma * N(0, 1)
local function noisy_circle(m, R, sigma)
  local t = {}
  for k = 0, m - 1 do
    local a = 2 * pi * k / m
    local r = R + sigma * gauss()
    t[#t + 1] = {r * cos(a), r * sin(a)}
  end
  return bs.points.new(t)
end

-- the square [0, s]^2 walked counter-clockwise, `per` points per side starting at a
-- corner (so corners are points 1, per+1, 2 per+1, 3 per+1), moved by sigma normal noise
local function square(s, per, sigma)
  local O = {{0, 0}, {s, 0}, {s, s}, {0, s}}
  local D = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}}
  local t = {}
  for c = 1, 4 do
    for j = 0, per - 1 do
      local e = sigma * gauss()
      local f = s * j / per
      -- the outward normal of side c is (D.y, -D.x)
      t[#t + 1] = {O[c][1] + f * D[c][1] + e * D[c][2], O[c][2] + f * D[c][2] - e * D[c][1]}
    end
  end
  return bs.points.new(t)
end

T.test("noise_sigma: ~0 on an exact circle, sigma within 20% on a noisy one", function()
  -- an exact circle leaves only what a local cubic cannot follow: the quartic term
  -- x^4 / (8 R^3) of the arc over the window of 9 points (|x| <= 4h), h the spacing
  for _, m in ipairs{100, 200, 400} do
    local h = 2 * pi * 10 / m
    local est = bs.geom.noise_sigma(noisy_circle(m, 10, 0))
    T.ok(est >= 0 and est < (4 * h) ^ 4 / (8 * 10 ^ 3), string.format("exact circle, m = %d: %g", m, est))
  end
  math.randomseed(20261122)
  for _, sigma in ipairs{0.01, 0.05} do
    local est = bs.geom.noise_sigma(noisy_circle(600, 10, sigma))
    T.ok(math.abs(est - sigma) <= 0.2 * sigma, string.format("estimate %g for %g", est, sigma))
  end
  T.raises(argerr(1, "noise_sigma", "noise estimate needs at least 6 points, got 5"),
           function() return bs.geom.noise_sigma(bs.points.new(5, 2)) end)
  T.raises(argerr(1, "noise_sigma", "point 3 has a non%-finite coordinate"),
           function() return bs.geom.noise_sigma({{0, 0}, {1, 0}, {0 / 0, 1}, {1, 1}, {0, 2}, {2, 2}}) end)
  T.fails("EDEGENERATE", bs.geom.noise_sigma, {{1, 1}, {1, 1}, {1, 1}, {1, 1}, {1, 1}, {1, 1}, {1, 1}})
end)

-- bs.geom.longest_step against the steps taken one by one in Lua, on random sequences of
-- 2D and 3D points, open and closed (the closing step counts only when closed)
T.test("longest_step: the longest of the steps, the closing one when closed", function()
  math.randomseed(20261207)
  for case = 1, 200 do
    local dim, m, t = case % 2 == 0 and 3 or 2, 3 + math.random(60), {}
    for i = 1, m do
      t[i] = {}
      for d = 1, dim do t[i][d] = (math.random() - 0.5) * 10 ^ math.random(-3, 3) end
    end
    local function step(i, j)
      local s = 0
      for d = 1, dim do s = s + (t[j][d] - t[i][d]) ^ 2 end
      return math.sqrt(s)
    end
    local open = 0
    for i = 2, m do open = math.max(open, step(i - 1, i)) end
    local closed = math.max(open, step(m, 1))
    local P = bs.points.new(t)
    T.ok(math.abs(bs.geom.longest_step(P) - closed) <= 1e-14 * closed, "closed, case " .. case)
    T.ok(math.abs(bs.geom.longest_step(P, { closed = false }) - open) <= 1e-14 * open, "open, case " .. case)
  end
  T.eq(bs.geom.longest_step({ {1, 1}, {1, 1}, {1, 1} }), 0, "coincident points")
  T.raises(argerr(1, "longest_step", "m = 2 points, at least 3 needed"),
           function() return bs.geom.longest_step({ {0, 0}, {1, 1} }) end)
  T.raises(argerr(1, "longest_step", "point 3 has a non%-finite coordinate"),
           function() return bs.geom.longest_step({ {0, 0}, {1, 0}, {0 / 0, 1} }) end)
end)

T.test("corners: a square has its 4 corners (turn 90), a circle none", function()
  for _, sigma in ipairs{0, 0.02} do
    math.randomseed(7)
    local P = square(10, 40, sigma)
    local idx, turn = bs.geom.corners(P, sigma > 0 and {sigma = sigma} or nil)
    T.eq(type(idx), "table"); T.eq(getmetatable(turn).__name, "bsfit.Vector")
    T.eq(#idx, 4, "corners with sigma " .. sigma); T.eq(#turn, 4)
    for c = 1, 4 do
      T.ok(math.abs(idx[c] - (40 * (c - 1) + 1)) <= 1, "corner " .. c .. " at point " .. idx[c])
      T.eq(math.type(idx[c]), "integer")
      T.near(turn:get(c), 90, 0.05, "turn at corner " .. c)
    end
  end
  local idx, turn = bs.geom.corners(noisy_circle(300, 5, 0))
  T.eq(#idx, 0); T.eq(#turn, 0)
  -- a right angle is not a corner when the smallest turn asked for is 100 degrees
  T.eq(#bs.geom.corners(square(10, 40, 0), {min_angle = 100}), 0)
  T.raises(argerr(2, "corners", "unknown option 'angle'"),
           function() return bs.geom.corners(square(10, 40, 0), {angle = 10}) end)
  T.raises(argerr(2, "corners", "field 'min_angle' must be in %[0, 180%)"),
           function() return bs.geom.corners(square(10, 40, 0), {min_angle = 180}) end)
  T.raises(argerr(2, "corners", "field 'scale' must be finite and >= 0"),
           function() return bs.geom.corners(square(10, 40, 0), {scale = -1}) end)
  T.raises(argerr(2, "corners", "field 'sigma' must be a number"),
           function() return bs.geom.corners(square(10, 40, 0), {sigma = "x"}) end)
  T.raises(argerr(1, "corners", "point 2 has a non%-finite coordinate"),
           function() return bs.geom.corners({{0, 0}, {0, math.huge}}) end)
end)
