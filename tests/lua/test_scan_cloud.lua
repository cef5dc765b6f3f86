-- test_scan_cloud.lua: centre-of-mass reduction, ordering into loops, and the scan
-- pipeline on noisy clouds (bs.scan.reduce, bs.scan.order, bsfit.scan.pipeline).
-- Truth: analytic curves (exact distances), true sampling orders, the synthetic shapes.
local T = require "tap"
local bs = require "bsfit"
local synth = require "scan_synth"
local pipeline = require "bsfit.scan.pipeline"

-- Closed test curves t in [0,1) -> x, y, with an exact (or dense-polyline) distance.
local function dense_distance(f)
  local n, px, py = 4000, nil, nil
  local X, Y = {}, {}
  for i = 0, n do X[i], Y[i] = f(i / n) end
  return function(x, y)
    local best = math.huge
    for i = 0, n - 1 do
      local dx, dy = X[i + 1] - X[i], Y[i + 1] - Y[i]
      local L2 = dx * dx + dy * dy
      local u = L2 > 0 and math.max(0, math.min(1, ((x - X[i]) * dx + (y - Y[i]) * dy) / L2)) or 0
      best = math.min(best, (X[i] + u * dx - x) ^ 2 + (Y[i] + u * dy - y) ^ 2)
    end
    return math.sqrt(best)
  end
end

local curves = {
  circle = function(t) return 5 * math.cos(2 * math.pi * t), 5 * math.sin(2 * math.pi * t) end,
  ellipse = function(t) return 6 * math.cos(2 * math.pi * t), 2 * math.sin(2 * math.pi * t) end,
  star = function(t)
    local r = 4 + 1.2 * math.cos(5 * 2 * math.pi * t)
    return r * math.cos(2 * math.pi * t), r * math.sin(2 * math.pi * t)
  end,
  -- a thick C: not star-shaped about its centroid (the outline of an annulus sector)
  cshape = function(t)
    local a0, a1, R, r = 0.6, 2 * math.pi - 0.6, 5, 3.5
    local L = { (a1 - a0) * R, R - r, (a1 - a0) * r, R - r }
    local tot = L[1] + L[2] + L[3] + L[4]
    local s = t * tot
    if s < L[1] then local a = a0 + s / R; return R * math.cos(a), R * math.sin(a) end
    s = s - L[1]
    if s < L[2] then local q = R - s; return q * math.cos(a1), q * math.sin(a1) end
    s = s - L[2]
    if s < L[3] then local a = a1 - s / r; return r * math.cos(a), r * math.sin(a) end
    s = s - L[3]
    local q = r + s
    return q * math.cos(a0), q * math.sin(a0)
  end,
}
local curve_names = { "circle", "ellipse", "star", "cshape" }

-- m points along curve f at evenly spaced parameters (with a random phase), shuffled;
-- returns the points and, for each, its true rank along the curve.
local function sample(f, m, r, noise, shuffle)
  local phase = r.uniform()
  local pts, rank = {}, {}
  for i = 1, m do
    local x, y = f((phase + (i - 1) / m) % 1)
    pts[i] = { x + (noise or 0) * r.normal(), y + (noise or 0) * r.normal() }
    rank[i] = i
  end
  if shuffle then
    for i = m, 2, -1 do
      local j = 1 + math.floor(r.uniform() * i) % i
      pts[i], pts[j] = pts[j], pts[i]
      rank[i], rank[j] = rank[j], rank[i]
    end
  end
  return pts, rank
end

T.test("reduction: every reduced point within a cell of the curve, and the curve within a cell of them", function()
  local r = synth.rng(3)
  for _, name in ipairs(curve_names) do
    local dist = dense_distance(curves[name])
    for _, cell in ipairs { 0.15, 0.4, 1.0 } do
      local pts = sample(curves[name], 6000, r, 0, true)
      local P = bs.points.new(pts)
      local R, w, used = bs.scan.reduce(P, { cell = cell })
      T.eq(used, cell)
      T.eq(#w, #R)
      T.near(w:sum(), #P, 1e-9, "the weights count every point")
      local worst = 0
      for i = 1, #R do worst = math.max(worst, dist(R:get(i))) end
      T.ok(worst < cell, ("%s cell %g: reduced point %.3g off the curve"):format(name, cell, worst))
      -- the other side: every curve sample near a reduced point
      local far = 0
      for i = 1, #pts, 37 do
        local best = math.huge
        for k = 1, #R do
          local x, y = R:get(k)
          best = math.min(best, math.sqrt((x - pts[i][1]) ^ 2 + (y - pts[i][2]) ^ 2))
        end
        far = math.max(far, best)
      end
      T.ok(far < cell, ("%s cell %g: curve point %.3g from the reduced points"):format(name, cell, far))
    end
  end
end)

T.test("reduction: weighted means, target counts, errors", function()
  local P = bs.points.new { { 0.1, 0.1 }, { 0.3, 0.3 }, { 1.5, 0.5 } }
  local R, w = bs.scan.reduce(P, { cell = 1, weights = { 1, 3, 2 } })
  T.eq(#R, 2)
  local x, y = R:get(1)
  T.near(x, 0.25, 1e-15); T.near(y, 0.25, 1e-15)
  T.eq(w:get(1), 4); T.eq(w:get(2), 2)
  local r = synth.rng(5)
  for _, target in ipairs { 50, 200, 700 } do
    local pts = sample(curves.star, 20000, r, 0.02, true)
    local R2, w2, cell = bs.scan.reduce(bs.points.new(pts), { target = target })
    T.ok(math.abs(#R2 - target) <= 0.1 * target, ("target %d gave %d (cell %g)"):format(target, #R2, cell))
    T.near(w2:sum(), #pts, 1e-6)
  end
  T.raises({ match = "exactly one of cell" }, function() bs.scan.reduce(P, { cell = 1, target = 3 }) end)
  T.raises({ match = "exactly one of cell" }, function() bs.scan.reduce(P, {}) end)
  T.raises({ match = "2D points" }, function() bs.scan.reduce(bs.points.new { { 1, 2, 3 } }, { cell = 1 }) end)
  T.raises({ match = "non%-finite" }, function() bs.scan.reduce(bs.points.new { { 0 / 0, 2 } }, { cell = 1 }) end)
  T.fails("EDEGENERATE", bs.scan.reduce, bs.points.new { { 1, 1 }, { 1, 1 } }, { target = 1 })
end)

-- Whether loop (a list of input indices) visits the true ranks in cyclic order, in
-- either direction (open: in sequence, either direction).
local function follows(index, rank, m, closed)
  local n = #index
  if n ~= m then return false, "loop of " .. n .. " points, want " .. m end
  for _, dir in ipairs { 1, -1 } do
    local good = true
    for i = 1, n - (closed and 0 or 1) do
      local a, b = rank[index[i]], rank[index[i % n + 1]]
      local step = (b - a) * dir
      if closed then step = step % m end
      if step ~= 1 then good = false; break end
    end
    if good then return true end
  end
  return false, "order broken"
end

T.test("ordering recovers the true order: star-shaped and not, closed and open", function()
  local r = synth.rng(17)
  for _, name in ipairs(curve_names) do
    -- the sampling must resolve the walls of the C (1.5 apart): spacing below half of it
    for _, m in ipairs(name == "cshape" and { 100, 300, 2000 } or { 40, 300, 2000 }) do
      local pts, rank = sample(curves[name], m, r, 0, true)
      local loops, rep = bs.scan.order(bs.points.new(pts))
      T.eq(#loops, 1, name .. " " .. m .. ": " .. rep.message)
      T.ok(loops[1].closed, name .. " closed")
      local ok, why = follows(loops[1].index, rank, m, true)
      T.ok(ok, ("%s m=%d (%s): %s"):format(name, m, rep.method, tostring(why)))
      if name == "cshape" then T.eq(rep.method, "graph", "the C is not star-shaped") end
      if name == "circle" then T.eq(rep.method, "angle") end
      -- counter-clockwise
      local a = 0
      local P = loops[1].points
      for i = 1, #P do
        local x0, y0 = P:get(i)
        local x1, y1 = P:get(i % #P + 1)
        a = a + x0 * y1 - x1 * y0
      end
      T.ok(a > 0, name .. ": counter-clockwise")
      local g = bs.scan.order(bs.points.new(pts), { method = "graph" })
      T.ok(follows(g[1].index, rank, m, true), name .. ": graph method on its own")
    end
  end
  -- open arcs: one open loop in sequence. An opening is seen when it is wider than gap (4)
  -- times the distance to the 2nd neighbour, about 8 sample spacings.
  for _, c in ipairs { { 30, 2 / 3 }, { 500, 5 / 6 }, { 2000, 0.95 } } do
    local m, span = c[1], c[2]
    local arc = function(t) local a = t * span * 2 * math.pi; return 3 * math.cos(a), 3 * math.sin(a) end
    local pts, rank = {}, {}
    for i = 1, m do pts[i] = { arc((i - 1) / (m - 1)) }; rank[i] = i end
    for i = m, 2, -1 do local j = 1 + (i * 7919) % i; pts[i], pts[j] = pts[j], pts[i]; rank[i], rank[j] = rank[j], rank[i] end
    local loops, rep = bs.scan.order(bs.points.new(pts))
    T.eq(#loops, 1)
    T.eq(loops[1].closed, false, "the C is open: " .. rep.message)
    T.eq(rep.open, 1)
    T.ok(follows(loops[1].index, rank, m, false), "open arc in sequence")
    T.raises({ match = "star" }, function() assert(bs.scan.order(bs.points.new(pts), { method = "angle" })) end)
  end
  -- two circles: two loops, each in order; an outlier pair is dropped
  local pts = {}
  for i = 1, 100 do local a = 2 * math.pi * i / 100; pts[#pts + 1] = { -4 + math.cos(a), math.sin(a) } end
  for i = 1, 60 do local a = 2 * math.pi * i / 60; pts[#pts + 1] = { 4 + math.cos(a), math.sin(a) } end
  pts[#pts + 1] = { 0, 10 }; pts[#pts + 1] = { 0.01, 10 }
  local loops, rep = bs.scan.order(bs.points.new(pts))
  T.eq(#loops, 2, rep.message)
  T.eq(rep.dropped, 2)
  T.ok(loops[1].closed and loops[2].closed)
  T.eq(#loops[1].points + #loops[2].points, 160)
end)

T.test("ordering a thin-walled section and a thick slab does not zigzag", function()
  local r = synth.rng(23)
  -- a slab: points spread across a band 0.3 wide around a circle of radius 5, reduced first
  local pts = {}
  for i = 1, 20000 do
    local a, d = 2 * math.pi * r.uniform(), 0.3 * (r.uniform() - 0.5)
    pts[i] = { (5 + d) * math.cos(a), (5 + d) * math.sin(a) }
  end
  local function crossings(P)
    local n, c = #P, 0
    local function seg(i) local a, b = { P:get(i) }, { P:get(i % n + 1) }; return a, b end
    local function orient(a, b, q) return (b[1] - a[1]) * (q[2] - a[2]) - (b[2] - a[2]) * (q[1] - a[1]) end
    for i = 1, n do
      local a, b = seg(i)
      for j = i + 2, n do
        if not (i == 1 and j == n) then
          local p, q = seg(j)
          if orient(a, b, p) * orient(a, b, q) < 0 and orient(p, q, a) * orient(p, q, b) < 0 then c = c + 1 end
        end
      end
    end
    return c
  end
  for _, cell in ipairs { 0.3, 0.6 } do
    local R = bs.scan.reduce(bs.points.new(pts), { cell = cell })
    for _, method in ipairs { "graph", "auto" } do
      local loops = bs.scan.order(R, { method = method })
      T.eq(#loops, 1)
      local P, L, back = loops[1].points, 0, 0
      for i = 1, #P do
        local x0, y0 = P:get(i)
        local x1, y1 = P:get(i % #P + 1)
        L = L + math.sqrt((x1 - x0) ^ 2 + (y1 - y0) ^ 2)
        local d = (math.atan(y1, x1) - math.atan(y0, x0) + math.pi) % (2 * math.pi) - math.pi
        back = math.min(back, 5 * d)
      end
      -- it goes round once, never back by more than a cell, never crossing itself
      T.ok(-back < cell, ("cell %g: a step goes back %.3g along the section"):format(cell, -back))
      T.eq(crossings(P), 0, "a simple polygon")
      -- cells twice the slab's width leave one point across it: no zigzag at all
      if cell == 0.6 then
        T.ok(L < 2 * math.pi * 5 * 1.15, ("tour %.2f vs circumference %.2f"):format(L, 2 * math.pi * 5))
      end
    end
  end
  -- a thin U-shaped wall: arms 1.0 apart, sampled every 0.2
  local u = function(t)
    local segs = { { -3, 4, -3, -3 }, { -3, -3, 3, -3 }, { 3, -3, 3, 4 }, { 3, 4, 2, 4 }, { 2, 4, 2, -2 },
                   { 2, -2, -2, -2 }, { -2, -2, -2, 4 }, { -2, 4, -3, 4 } }
    local lens, tot = {}, 0
    for i, s in ipairs(segs) do lens[i] = math.sqrt((s[3] - s[1]) ^ 2 + (s[4] - s[2]) ^ 2); tot = tot + lens[i] end
    local d = t * tot
    for i, s in ipairs(segs) do
      if d <= lens[i] or i == #segs then
        local q = d / lens[i]
        return s[1] + q * (s[3] - s[1]), s[2] + q * (s[4] - s[2])
      end
      d = d - lens[i]
    end
  end
  local up, rank = sample(u, 200, r, 0, true)
  local lu, rep = bs.scan.order(bs.points.new(up))
  T.eq(#lu, 1, rep.message)
  T.ok(follows(lu[1].index, rank, 200, true), "thin U in order")
end)

-- {======================================================================
-- The pipeline on clouds
-- =======================================================================

local function cloud_scan(P) return function() return { points = bs.points.new(P), kind = "cloud" } end end

T.test("cloud pipeline: every section within 2 noise + cell/2 (+ the slab's slope) of the truth", function()
  for _, c in ipairs { { "vase", 0.02, 0.12, 3 }, { "box", 0.01, 0.1, 1 }, { "wing", 0.005, 0.05, 4 } } do
    local sh = synth.shapes[c[1]]()
    local noise, cell, uneven = c[2], c[3], c[4]
    local P = synth.cloud(sh, { n = 60000, noise = noise, uneven = uneven, seed = #c[1] })
    local thick = 0.1
    local res = pipeline.run("synthetic", { read = cloud_scan(P), slices = 4, thickness = thick, cell = cell })
    T.eq(#res.rows, 4)
    for _, row in ipairs(res.rows) do
      T.eq(row.status, "ok", c[1] .. ": " .. tostring(row.message))
    end
    for _, cv in ipairs(res.curves) do
      local z = cv.slice.position
      -- the slab mixes heights z +- thick/2: the section moves by at most slope * thick/2
      local x1, y1 = sh.point(z - thick / 2, 0.1)
      local x2, y2 = sh.point(z + thick / 2, 0.1)
      local slope = 0
      for t = 0, 1, 0.01 do
        local a, b = sh.point(z - thick / 2, t)
        local p, q = sh.point(z + thick / 2, t)
        slope = math.max(slope, math.sqrt((p - a) ^ 2 + (q - b) ^ 2) / 2)
      end
      local bound = 2 * noise + cell / 2 + slope + 0 * (x1 + y1 + x2 + y2)
      local S, worst = cv.curve:sample(300), 0
      for i = 1, #S do worst = math.max(worst, sh.distance(z, S:get(i))) end
      T.ok(worst <= bound, ("%s z=%.2f: %.4g from the truth, bound %.4g"):format(c[1], z, worst, bound))
    end
    T.eq(#res.curves3d, 4)
    -- the 3D curve is the 2D one in the slice's frame
    local C3, C2, sl = res.curves3d[2], res.curves[2].curve, res.curves[2].slice
    local p3, p2 = { C3:eval(0.3) }, { C2:eval(0.3) }
    T.near(p3[3], sl.position, 1e-9)
    T.near(p3[1], p2[1], 1e-9); T.near(p3[2], p2[2], 1e-9)
  end
end)

T.test("cloud pipeline: empty slabs, two loops, bad options; the other slices still run", function()
  local sh = synth.shapes.legs()
  local P = synth.cloud(sh, { n = 20000, noise = 0.005, seed = 2 })
  local res = pipeline.run("legs", { read = cloud_scan(P), at = { 2, 5, 50 }, thickness = 0.1, cell = 0.1 })
  local by = {}
  for _, row in ipairs(res.rows) do by[row.slice] = by[row.slice] or {}; table.insert(by[row.slice], row) end
  T.eq(#by[1], 2, "two legs: two loops")
  T.eq(by[1][1].status, "ok"); T.eq(by[1][2].status, "ok"); T.eq(by[1][1].loops, 2)
  T.eq(#by[2], 2)
  T.eq(#by[3], 1)
  T.eq(by[3][1].status, "error")
  T.ok(by[3][1].message:find("empty slab"), by[3][1].message)
  T.eq(#res.curves3d, 4)
  T.raises({ match = "unknown option 'slice_count'" }, function() pipeline.run("x", { slice_count = 3 }) end)
  T.raises({ match = "step 'order' must be a function" }, function() pipeline.run("x", { order = 3 }) end)
  -- a replaced step is used
  local calls = 0
  local res2 = pipeline.run("legs", { read = cloud_scan(P), at = { 2 }, thickness = 0.1, cell = 0.1,
    order = function(R, ctx) calls = calls + 1; return bs.scan.order(R, { method = "graph" }) end })
  T.eq(calls, 1)
  T.eq(#res2.curves, 2)
end)

-- }======================================================================

T.test("cloud slabs along any direction: projected points on the exact circles of a sphere", function()
  local r = synth.rng(31)
  for trial = 1, 8 do
    local c = { 10 * r.uniform() - 5, 10 * r.uniform() - 5, 10 * r.uniform() - 5 }
    local R = 1 + 3 * r.uniform()
    local P = {}
    for i = 1, 20000 do
      local x, y, z = r.normal(), r.normal(), r.normal()
      local n = math.sqrt(x * x + y * y + z * z)
      P[i] = { c[1] + R * x / n, c[2] + R * y / n, c[3] + R * z / n }
    end
    local d = { r.uniform() - 0.5, r.uniform() - 0.5, r.uniform() - 0.5 }
    local len = math.sqrt(d[1] ^ 2 + d[2] ^ 2 + d[3] ^ 2)
    local n = { d[1] / len, d[2] / len, d[3] / len }
    local h0 = n[1] * c[1] + n[2] * c[2] + n[3] * c[3]
    local T0 = 0.01
    local at = { h0 - 0.5 * R, h0, h0 + 0.7 * R }
    local S = bs.scan.slice(bs.points.new(P), { direction = d, at = at, thickness = T0 })
    for k, s in ipairs(S) do
      T.near(s.position, at[k], 1e-12)
      local off = at[k] - h0
      local rho = math.sqrt(R * R - off * off)
      -- the circle's centre in the slice's frame
      local q = { c[1] - s.origin[1], c[2] - s.origin[2], c[3] - s.origin[3] }
      local cu = q[1] * s.u[1] + q[2] * s.u[2] + q[3] * s.u[3]
      local cv = q[1] * s.v[1] + q[2] * s.v[2] + q[3] * s.v[3]
      -- within the slab the radius varies by at most |d rho / d h| * T0/2
      local slack = (math.abs(off) + T0) / math.sqrt(math.max(R * R - (math.abs(off) + T0) ^ 2, 1e-12)) * T0 / 2
      T.ok(#s.points > 10, "slab populated")
      local worst = 0
      for i = 1, #s.points do
        local u, v = s.points:get(i)
        worst = math.max(worst, math.abs(math.sqrt((u - cu) ^ 2 + (v - cv) ^ 2) - rho))
      end
      T.ok(worst <= slack + 1e-9, ("trial %d slice %d: %.3g off the circle (slack %.3g)"):format(trial, k, worst, slack))
      T.near(s.normal[1], n[1], 1e-12); T.near(s.normal[2], n[2], 1e-12); T.near(s.normal[3], n[3], 1e-12)
    end
  end
end)
