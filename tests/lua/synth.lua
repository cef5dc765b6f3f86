-- tests/lua/synth.lua
-- Synthetic sections with known truth for the strategy tests: smooth closed shapes
-- r(theta), polygons with sharp corners, an airfoil, Gaussian noise from a seeded
-- generator, and the symmetric Hausdorff distance between a fitted curve and the truth.

local bs = require "bsfit"

local M = {}

-- xorshift-free LCG (deterministic across hosts) and Box-Muller
function M.rng(seed)
  local s = seed
  local function uniform()
    s = (s * 1103515245 + 12345) % 2147483648
    return (s + 0.5) / 2147483648
  end
  local function gauss()
    return math.sqrt(-2 * math.log(uniform())) * math.cos(2 * math.pi * uniform())
  end
  return uniform, gauss
end

-- smooth shapes of size ~2, as functions of t in [0, 2 pi)
M.smooth = {
  circle = function(t) return math.cos(t), math.sin(t) end,
  ellipse = function(t) return math.cos(t), 0.5 * math.sin(t) end,
  star = function(t) local r = 1 + 0.15 * math.cos(5 * t); return r * math.cos(t), r * math.sin(t) end,
  superellipse = function(t)
    local c, s = math.cos(t), math.sin(t)
    local sc = c < 0 and -1 or 1
    local ss = s < 0 and -1 or 1
    return sc * math.sqrt(math.abs(c)), ss * math.sqrt(math.abs(s))
  end,
}

-- A cam, size ~2.5: a smooth shape whose curvature changes all along it (tangent arcs
-- follow it within the noise, but farther from it than one smooth curve).
function M.cam(t)
  local r = 1 + 0.25 * math.cos(t) + 0.08 * math.cos(2 * t)
  return r * math.cos(t), r * math.sin(t)
end

-- The smooth shapes and the cam, and their names sorted (a sweep's draws must not depend
-- on the order pairs() gives):
--   local shapes, names = synth.smooth_shapes()
function M.smooth_shapes()
  local shapes, names = { cam = M.cam }, {}
  for name, f in pairs(M.smooth) do shapes[name] = f end
  for name in pairs(shapes) do names[#names + 1] = name end
  table.sort(names)
  return shapes, names
end

-- How many corners a result of the auto strategy has, on either path: the smooth path's
-- (rep.corners) and the pieces' corner joins.
function M.corners_of(rep)
  local n = #rep.corners
  for _, p in ipairs(rep.pieces or {}) do if p.join == "corner" then n = n + 1 end end
  return n
end

-- the warning of auto's misfit swap (pieces_path.lua: the smooth curve missed a sample by
-- 6 sigma, so the lines and arcs were fitted), or nil when it was not taken
function M.misfit_swap(rep)
  for _, w in ipairs(rep.warnings or {}) do
    if w:find("the smooth curve missed a sample", 1, true) then return w end
  end
  return nil
end

-- The checks of a smooth section's result (C, rep from auto.run): no loop, reported or
-- not (T.eq through `T`, tap's), and its name added to `cornered` when it shows a corner
-- (the callers count them and hold the count to 0).
function M.check_smooth(T, C, rep, what, cornered)
  if M.corners_of(rep) > 0 then cornered[#cornered + 1] = what end
  T.eq(rep.crossings, 0, what .. ": crossings")
  T.eq((bs.geom.self_intersections(C, 2000)), 0, what .. ": self-intersection")
end

-- points {x, y} of a smooth shape, m of them, uneven spacing when `uneven`
function M.sample_smooth(f, m, uneven)
  local pts = {}
  for i = 0, m - 1 do
    local t = 2 * math.pi * i / m
    if uneven then t = t + 0.3 * math.sin(2 * t) end
    local x, y = f(t)
    pts[#pts + 1] = { x, y }
  end
  return pts
end

-- m points of the smooth shape f with `bursts` clusters: (1 - bursts * frac) m points
-- evenly in t, and bursts times frac m points nearly coincident (spread over 1e-4 in
-- t) at evenly spaced places, as a scanner that lingers leaves them
function M.clustered(f, m, bursts, frac)
  local nb = math.floor(frac * m)
  local base = m - bursts * nb
  local pts = {}
  for i = 0, base - 1 do
    local t = 2 * math.pi * i / base
    pts[#pts + 1] = { f(t) }
    if i % (base // bursts) == base // (2 * bursts) then
      for b = 1, nb do pts[#pts + 1] = { f(t + 1e-4 * b / nb) } end
    end
  end
  return pts
end

-- m points evenly along a closed polygon given by its vertices
function M.sample_polygon(v, m)
  local per, len = 0, {}
  for i = 1, #v do
    local a, b = v[i], v[i % #v + 1]
    len[i] = math.sqrt((b[1] - a[1]) ^ 2 + (b[2] - a[2]) ^ 2)
    per = per + len[i]
  end
  local pts, e, acc = {}, 1, 0
  for i = 0, m - 1 do
    local pos = per * i / m
    while pos > acc + len[e] and e < #v do acc = acc + len[e]; e = e + 1 end
    local a, b = v[e], v[e % #v + 1]
    local f = (pos - acc) / len[e]
    pts[#pts + 1] = { a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2]) }
  end
  return pts
end

-- a D shape (half disc of radius 1) and a symmetric airfoil with a sharp trailing
-- edge, as dense truth polylines and sampled points
function M.d_shape(m)
  local pts, nl = {}, math.floor(m * 2 / (2 + math.pi))
  for i = 0, nl - 1 do pts[#pts + 1] = { -1 + 2 * i / nl, 0 } end
  for i = 0, m - nl - 1 do
    local t = math.pi * i / (m - nl)
    pts[#pts + 1] = { math.cos(t), math.sin(t) }
  end
  return pts
end

function M.airfoil(m)
  local pts = {}
  for i = 0, m - 1 do
    local t = 2 * math.pi * i / m
    local x = 0.5 * (1 + math.cos(t))
    local y = 0.6 * (0.2969 * math.sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x ^ 3 - 0.1036 * x ^ 4)
    pts[#pts + 1] = { x, t < math.pi and y or -y }
  end
  return pts
end

-- noisy copy of pts (table of {x, y}) as Points
function M.noisy(pts, sigma, seed)
  local _, gauss = M.rng(seed)
  local q = {}
  for i, p in ipairs(pts) do q[i] = { p[1] + sigma * gauss(), p[2] + sigma * gauss() } end
  return bs.points.new(q)
end

-- distance from point (x, y) to segment a-b
local function seg_dist(x, y, ax, ay, bx, by)
  local dx, dy = bx - ax, by - ay
  local l2 = dx * dx + dy * dy
  local t = l2 > 0 and ((x - ax) * dx + (y - ay) * dy) / l2 or 0
  if t < 0 then t = 0 elseif t > 1 then t = 1 end
  local ex, ey = ax + t * dx - x, ay + t * dy - y
  return math.sqrt(ex * ex + ey * ey)
end

-- one-sided distance: max over points of A of the distance to the closed polyline B,
-- searched in a grid of B's edges (exact: rings of cells around a point are searched
-- until no unsearched cell can hold a nearer edge)
local function directed(A, B)
  local n = #B
  local x0, y0, x1, y1 = math.huge, math.huge, -math.huge, -math.huge
  for i = 1, n do
    x0, y0 = math.min(x0, B[i][1]), math.min(y0, B[i][2])
    x1, y1 = math.max(x1, B[i][1]), math.max(y1, B[i][2])
  end
  local cell = math.max(x1 - x0, y1 - y0, 1e-12) / 64
  local grid = {}
  for j = 1, n do
    local a, b = B[j], B[j % n + 1]
    for cx = math.floor((math.min(a[1], b[1]) - x0) / cell), math.floor((math.max(a[1], b[1]) - x0) / cell) do
      for cy = math.floor((math.min(a[2], b[2]) - y0) / cell), math.floor((math.max(a[2], b[2]) - y0) / cell) do
        local key = cx * 1048576 + cy
        local l = grid[key]
        if not l then l = {}; grid[key] = l end
        l[#l + 1] = j
      end
    end
  end
  local worst = 0
  for i = 1, #A do
    local x, y = A[i][1], A[i][2]
    local cx, cy = math.floor((x - x0) / cell), math.floor((y - y0) / cell)
    local best, r = math.huge, 0
    while true do
      for dx = -r, r do
        for dy = -r, r do
          if math.max(math.abs(dx), math.abs(dy)) == r then
            local l = grid[(cx + dx) * 1048576 + cy + dy]
            if l then
              for _, j in ipairs(l) do
                local a, b = B[j], B[j % n + 1]
                local d = seg_dist(x, y, a[1], a[2], b[1], b[2])
                if d < best then best = d end
              end
            end
          end
        end
      end
      if best <= r * cell or r > 256 then break end
      r = r + 1
    end
    if best > worst then worst = best end
  end
  return worst
end

-- the closed polyline pts with every edge cut into pieces no longer than h
local function densify(pts, h)
  local out, n = {}, #pts
  for i = 1, n do
    local a, b = pts[i], pts[i % n + 1]
    local k = math.max(1, math.ceil(math.sqrt((b[1] - a[1]) ^ 2 + (b[2] - a[2]) ^ 2) / h))
    for j = 0, k - 1 do
      out[#out + 1] = { a[1] + (b[1] - a[1]) * j / k, a[2] + (b[2] - a[2]) * j / k }
    end
  end
  return out
end

local function samples(C, k)
  local S, A = C:sample(k), {}
  for i = 1, #S do local x, y = S:get(i); A[i] = { x, y } end
  return A
end

-- symmetric Hausdorff distance between curve C and the closed truth polyline `truth`
-- (table of {x, y}): from k samples of C (default 600) to the truth, and from the truth
-- (its edges cut to a thousandth of its extent) to 4000 samples of C (fewer would cut
-- C's own corners by more than the noise of the tests)
function M.hausdorff(C, truth, k)
  local lo, hi = math.huge, -math.huge
  for _, p in ipairs(truth) do lo = math.min(lo, p[1], p[2]); hi = math.max(hi, p[1], p[2]) end
  return math.max(directed(samples(C, k or 600), truth),
                  directed(densify(truth, 1e-3 * (hi - lo)), samples(C, 4000)))
end

-- true when the closed polyline of k samples of C crosses itself
function M.self_intersects(C, k)
  local S = C:sample(k or 400)
  local n, p = #S, {}
  for i = 1, n do local x, y = S:get(i); p[i] = { x, y } end
  local function cross(o, a, b) return (a[1] - o[1]) * (b[2] - o[2]) - (a[2] - o[2]) * (b[1] - o[1]) end
  for i = 1, n do
    local a, b = p[i], p[i % n + 1]
    for j = i + 2, n do
      if not (i == 1 and j == n) then
        local c, d = p[j], p[j % n + 1]
        local d1, d2 = cross(a, b, c), cross(a, b, d)
        local d3, d4 = cross(c, d, a), cross(c, d, b)
        if d1 * d2 < 0 and d3 * d4 < 0 then return true end
      end
    end
  end
  return false
end

-- Does the closed polyline S (a table of {x, y}) cross itself? Two edges that are not
-- neighbours and cross properly; edges bucketed on a grid of about #S cells, so that
-- 10^4 edges take milliseconds (the O(k^2) check above is for a few hundred).
function M.polyline_crosses(S)
  local n, x0, y0, x1, y1 = #S, math.huge, math.huge, -math.huge, -math.huge
  for _, p in ipairs(S) do
    x0, y0, x1, y1 = math.min(x0, p[1]), math.min(y0, p[2]), math.max(x1, p[1]), math.max(y1, p[2])
  end
  local g = math.max(1, math.floor(math.sqrt(n)))
  local cw, ch = (x1 - x0) / g + 1e-300, (y1 - y0) / g + 1e-300
  local function cross(o, a, b) return (a[1] - o[1]) * (b[2] - o[2]) - (a[2] - o[2]) * (b[1] - o[1]) end
  local function proper(i, j)
    local a, b, c, d = S[i], S[i % n + 1], S[j], S[j % n + 1]
    return cross(a, b, c) * cross(a, b, d) < 0 and cross(c, d, a) * cross(c, d, b) < 0
  end
  local cells = {}
  for i = 1, n do
    local a, b = S[i], S[i % n + 1]
    for cx = math.floor((math.min(a[1], b[1]) - x0) / cw), math.floor((math.max(a[1], b[1]) - x0) / cw) do
      for cy = math.floor((math.min(a[2], b[2]) - y0) / ch), math.floor((math.max(a[2], b[2]) - y0) / ch) do
        local key = cx * (g + 2) + cy
        local list = cells[key] or {}
        cells[key] = list
        for _, j in ipairs(list) do
          if j ~= i - 1 and not (i == n and j == 1) and proper(i, j) then return true end
        end
        list[#list + 1] = i
      end
    end
  end
  return false
end

-- Samples of the closed curve C as {x, y}: k even ones, and 20 on either side of every
-- inner knot at 2^-1 .. 2^-20 of a thousandth of the domain (a loop at a corner can be
-- that small).
function M.dense_samples(C, k)
  local a, b = C:domain()
  local us = {}
  for j = 0, (k or 6000) - 1 do us[#us + 1] = a + (b - a) * j / (k or 6000) end
  for _, t in ipairs(C:knots():totable()) do
    if t > a and t < b then
      for e = 1, 20 do
        local h = (b - a) * 1e-3 * 2 ^ -e
        us[#us + 1], us[#us + 2] = t - h, t + h
      end
    end
  end
  table.sort(us)
  local S, last = {}, nil
  for _, u in ipairs(us) do
    if u >= a and u < b and u ~= last then S[#S + 1] = { C:eval(u) }; last = u end
  end
  return S
end

return M
