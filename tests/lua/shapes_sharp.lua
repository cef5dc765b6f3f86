-- tests/lua/shapes_sharp.lua
-- Sections built from straight lines and circular arcs, known exactly (issue 14): block
-- letters with and without serifs, D shapes, slots, keyholes, gears, rounded rectangles,
-- polygons with fillets; sampled at a chosen number of points per side, evenly or
-- unevenly, with seeded Gaussian noise; and the exact distance of a point to the true
-- outline, so the Hausdorff distance of a fitted curve to the truth is exact up to the
-- density of the samples taken of the curve.
--
-- An outline is a list of primitives, in order, each ending where the next starts:
--   {kind = "line", a = {x, y}, b = {x, y}}
--   {kind = "arc", c = {x, y}, r = r, a0 = start angle, sweep = signed angle}
-- plus `corners`, the points where two primitives meet at an angle.

local M = {}

local pi = math.pi

-- {======================================================================
-- Primitives
-- =======================================================================

local function line(a, b) return { kind = "line", a = a, b = b } end
local function arc(c, r, a0, sweep) return { kind = "arc", c = c, r = r, a0 = a0, sweep = sweep } end

-- the point at fraction f of primitive q, and its length
local function at(q, f)
  if q.kind == "line" then
    return { q.a[1] + f * (q.b[1] - q.a[1]), q.a[2] + f * (q.b[2] - q.a[2]) }
  end
  local t = q.a0 + f * q.sweep
  return { q.c[1] + q.r * math.cos(t), q.c[2] + q.r * math.sin(t) }
end
M.at = at

local function length(q)
  if q.kind == "line" then return math.sqrt((q.b[1] - q.a[1]) ^ 2 + (q.b[2] - q.a[2]) ^ 2) end
  return q.r * math.abs(q.sweep)
end

-- unit tangent of q at fraction f
local function tangent(q, f)
  if q.kind == "line" then
    local l = length(q)
    return { (q.b[1] - q.a[1]) / l, (q.b[2] - q.a[2]) / l }
  end
  local t, s = q.a0 + f * q.sweep, q.sweep > 0 and 1 or -1
  return { -s * math.sin(t), s * math.cos(t) }
end

-- exact distance from (x, y) to primitive q
local function dist_to(q, x, y)
  if q.kind == "line" then
    local dx, dy = q.b[1] - q.a[1], q.b[2] - q.a[2]
    local l2 = dx * dx + dy * dy
    local t = math.max(0, math.min(1, ((x - q.a[1]) * dx + (y - q.a[2]) * dy) / l2))
    return math.sqrt((q.a[1] + t * dx - x) ^ 2 + (q.a[2] + t * dy - y) ^ 2)
  end
  -- angle of the point measured from a0 in the sweep's direction
  local th = math.atan(y - q.c[2], x - q.c[1])
  local rel = (q.sweep > 0 and (th - q.a0) or (q.a0 - th)) % (2 * pi)
  if rel <= math.abs(q.sweep) then
    return math.abs(math.sqrt((x - q.c[1]) ^ 2 + (y - q.c[2]) ^ 2) - q.r)
  end
  local p0, p1 = at(q, 0), at(q, 1)
  return math.min(math.sqrt((x - p0[1]) ^ 2 + (y - p0[2]) ^ 2), math.sqrt((x - p1[1]) ^ 2 + (y - p1[2]) ^ 2))
end

-- }======================================================================

-- {======================================================================
-- Outlines
-- =======================================================================

-- The outline of a polygon (counter-clockwise vertices) whose vertex k is rounded by a
-- fillet of radius r[k] (0 or nil: a sharp corner). A fillet of radius r at a turn of
-- angle th starts r tan(th/2) before the vertex, on both sides.
function M.filleted(v, r)
  local n, prims, corners = #v, {}, {}
  local cut = {}
  local function dir(a, b)
    local l = math.sqrt((b[1] - a[1]) ^ 2 + (b[2] - a[2]) ^ 2)
    return { (b[1] - a[1]) / l, (b[2] - a[2]) / l }
  end
  for k = 1, n do
    local rk = r and r[k] or 0
    local d1, d2 = dir(v[(k - 2) % n + 1], v[k]), dir(v[k], v[k % n + 1])
    local cross, dot = d1[1] * d2[2] - d1[2] * d2[1], d1[1] * d2[1] + d1[2] * d2[2]
    local th = math.atan(cross, dot)
    if rk > 0 then
      local t = rk * math.tan(math.abs(th) / 2)
      local p, q = { v[k][1] - t * d1[1], v[k][2] - t * d1[2] }, { v[k][1] + t * d2[1], v[k][2] + t * d2[2] }
      local s = th > 0 and 1 or -1 -- left turn: centre on the left
      local c = { p[1] - s * rk * d1[2], p[2] + s * rk * d1[1] }
      cut[k] = { p = p, q = q, arc = arc(c, rk, math.atan(p[2] - c[2], p[1] - c[1]), th) }
    else
      cut[k] = { p = v[k], q = v[k] }
      corners[#corners + 1] = v[k]
    end
  end
  for k = 1, n do
    if cut[k].arc then prims[#prims + 1] = cut[k].arc end
    prims[#prims + 1] = line(cut[k].q, cut[(k % n) + 1].p)
  end
  return { prims = prims, corners = corners }
end

-- A D shape: the half disc of radius R above the x axis.
function M.d_shape(R)
  return { prims = { line({ -R, 0 }, { R, 0 }), arc({ 0, 0 }, R, 0, pi) },
           corners = { { -R, 0 }, { R, 0 } } }
end

-- A slot (stadium): length L between the centres of its two half circles of radius R.
function M.slot(L, R)
  return { prims = { line({ 0, -R }, { L, -R }), arc({ L, 0 }, R, -pi / 2, pi),
                     line({ L, R }, { 0, R }), arc({ 0, 0 }, R, pi / 2, pi) }, corners = {} }
end

-- A keyhole: a circle of radius R on a slot of width 2w (w < R) and depth D below it.
function M.keyhole(R, w, D)
  local h = math.sqrt(R * R - w * w)
  local a0 = math.atan(-h, w) -- where the slot's right side meets the circle
  local sweep = 2 * pi - 2 * (a0 + pi / 2)
  return { prims = { arc({ 0, 0 }, R, a0, sweep), line({ -w, -h }, { -w, -h - D }),
                     line({ -w, -h - D }, { w, -h - D }), line({ w, -h - D }, { w, -h }) },
           corners = { { -w, -h }, { -w, -h - D }, { w, -h - D }, { w, -h } } }
end

-- A gear of z trapezoidal teeth between radii r1 < r2 (a polygon).
function M.gear(z, r1, r2)
  local v = {}
  for k = 0, z - 1 do
    local a = 2 * pi * k / z
    local s = 2 * pi / z
    for _, t in ipairs { { 0, r1 }, { 0.3, r1 }, { 0.45, r2 }, { 0.8, r2 }, { 0.95, r1 } } do
      v[#v + 1] = { t[2] * math.cos(a + t[1] * s), t[2] * math.sin(a + t[1] * s) }
    end
  end
  -- consecutive root points on r1 (0.95 of one tooth, 0 of the next) are joined by a line
  return M.filleted(v)
end

-- Block letters (counter-clockwise polygons), optionally with serifs.
local letters = {
  T = { { 2, 0 }, { 3, 0 }, { 3, 4 }, { 5, 4 }, { 5, 5 }, { 0, 5 }, { 0, 4 }, { 2, 4 } },
  L = { { 0, 0 }, { 4, 0 }, { 4, 1 }, { 1, 1 }, { 1, 5 }, { 0, 5 } },
  E = { { 0, 0 }, { 4, 0 }, { 4, 1 }, { 1, 1 }, { 1, 2 }, { 3, 2 }, { 3, 3 }, { 1, 3 }, { 1, 4 },
        { 4, 4 }, { 4, 5 }, { 0, 5 } },
  H = { { 0, 0 }, { 1, 0 }, { 1, 2 }, { 3, 2 }, { 3, 0 }, { 4, 0 }, { 4, 5 }, { 3, 5 }, { 3, 3 },
        { 1, 3 }, { 1, 5 }, { 0, 5 } },
  -- with serifs: the stems widen at their ends
  Ts = { { 1.6, 0 }, { 3.4, 0 }, { 3.4, 0.3 }, { 3, 0.3 }, { 3, 4 }, { 4.7, 4 }, { 4.7, 3.7 },
         { 5, 3.7 }, { 5, 5 }, { 0, 5 }, { 0, 3.7 }, { 0.3, 3.7 }, { 0.3, 4 }, { 2, 4 }, { 2, 0.3 },
         { 1.6, 0.3 } },
  Ls = { { 0, 0 }, { 4, 0 }, { 4, 1.3 }, { 3.7, 1.3 }, { 3.7, 1 }, { 1, 1 }, { 1, 4.7 }, { 1.3, 4.7 },
         { 1.3, 5 }, { -0.3, 5 }, { -0.3, 4.7 }, { 0, 4.7 } },
}

function M.letter(name) return M.filleted(letters[name]) end

-- A random polygon of n vertices (counter-clockwise, spread round a circle, each a third
-- of its share of the turn off even) with fillets, as the caller draws them: radius(k) the
-- k-th vertex's distance from the centre (1 when nil); fillet(room) the radius of the
-- fillet at a vertex where one of radius `room` would take a third of each side beside it
-- (0: a sharp corner). uniform: the caller's draws (shapes.rng).
function M.random_filleted(uniform, n, radius, fillet)
  local v, r = {}, {}
  local a0 = 2 * pi * uniform()
  for k = 1, n do
    local a = a0 + 2 * pi * (k - 1 + 0.3 * (uniform() - 0.5)) / n
    local R = radius and radius(k) or 1
    v[k] = { R * math.cos(a), R * math.sin(a) }
  end
  for k = 1, n do
    local p, q, w = v[(k - 2) % n + 1], v[k], v[k % n + 1]
    local d1, d2 = { q[1] - p[1], q[2] - p[2] }, { w[1] - q[1], w[2] - q[2] }
    local l1, l2 = math.sqrt(d1[1] ^ 2 + d1[2] ^ 2), math.sqrt(d2[1] ^ 2 + d2[2] ^ 2)
    local turn = math.acos(math.max(-1, math.min(1, (d1[1] * d2[1] + d1[2] * d2[2]) / (l1 * l2))))
    r[k] = fillet(math.min(l1, l2) / 3 / math.tan(turn / 2))
  end
  return M.filleted(v, r)
end

-- A rounded rectangle w x h with fillets of radius r.
function M.rounded_rect(w, h, r)
  return M.filleted({ { 0, 0 }, { w, 0 }, { w, h }, { 0, h } }, { r, r, r, r })
end

-- A regular n-gon of circumradius R with fillets of radius r at every other vertex.
function M.filleted_polygon(n, R, r)
  local v, rr = {}, {}
  for k = 0, n - 1 do
    v[#v + 1] = { R * math.cos(2 * pi * k / n), R * math.sin(2 * pi * k / n) }
    rr[#rr + 1] = k % 2 == 0 and r or 0
  end
  return M.filleted(v, rr)
end

-- Every outline of the generator, by name.
function M.all()
  return {
    D = M.d_shape(10), slot = M.slot(6, 2), keyhole = M.keyhole(3, 1.2, 4), gear = M.gear(8, 4, 5),
    T = M.letter("T"), L = M.letter("L"), E = M.letter("E"), H = M.letter("H"),
    T_serif = M.letter("Ts"), L_serif = M.letter("Ls"), rrect = M.rounded_rect(60, 30, 1.5),
    hexagon = M.filleted_polygon(6, 5, 1), pentagon = M.filleted_polygon(5, 5, 1.5),
  }
end

-- The names of every outline, sorted (a stable order for sweeps and their messages).
function M.names()
  local names = {}
  for k in pairs(M.all()) do names[#names + 1] = k end
  table.sort(names)
  return names
end

-- the distance between two 2D points {x, y}
function M.dist(a, b) return math.sqrt((a[1] - b[1]) ^ 2 + (a[2] - b[2]) ^ 2) end

-- }======================================================================

-- {======================================================================
-- Sampling, noise, distances
-- =======================================================================

-- LCG (deterministic everywhere) and Box-Muller
function M.rng(seed)
  local s = seed
  local function uniform()
    s = (s * 1103515245 + 12345) % 2147483648
    return (s + 0.5) / 2147483648
  end
  local function gauss() return math.sqrt(-2 * math.log(uniform())) * math.cos(2 * pi * uniform()) end
  return uniform, gauss
end

-- The size of an outline: its bounding-box diagonal.
function M.size(o)
  local lo, hi = { math.huge, math.huge }, { -math.huge, -math.huge }
  for _, q in ipairs(o.prims) do
    for f = 0, 1, 1 / 64 do
      local p = at(q, f)
      for d = 1, 2 do lo[d] = math.min(lo[d], p[d]); hi[d] = math.max(hi[d], p[d]) end
    end
  end
  return math.sqrt((hi[1] - lo[1]) ^ 2 + (hi[2] - lo[2]) ^ 2)
end

-- Samples of outline o: per primitive k = per(q) points (a number, or a function of the
-- primitive), evenly at fractions (j - 1/2)/k (so corners lie between samples) or, with
-- `uneven`, at sorted random fractions; with `bare` = b, evenly over the fractions [b, 1 - b]
-- only (each end of every primitive left unsampled over b of it); noise sigma (absolute)
-- with `seed`.
-- Returns a table of {x, y}.
function M.sample(o, per, opts)
  opts = opts or {}
  local uniform, gauss = M.rng(opts.seed or 1)
  local pts = {}
  for _, q in ipairs(o.prims) do
    local k = type(per) == "function" and per(q) or per
    local fs = {}
    for j = 1, k do
      if opts.uneven then
        fs[j] = 0.05 + 0.9 * uniform()
      elseif opts.bare then
        fs[j] = opts.bare + (1 - 2 * opts.bare) * (j - 1) / (k - 1)
      else
        fs[j] = (j - 0.5) / k
      end
    end
    table.sort(fs)
    for _, f in ipairs(fs) do
      local p = at(q, f)
      local s = opts.sigma or 0
      if s > 0 then p = { p[1] + s * gauss(), p[2] + s * gauss() } end
      pts[#pts + 1] = p
    end
  end
  return pts
end

-- exact distance from (x, y) to the outline
function M.distance(o, x, y)
  local d = math.huge
  for _, q in ipairs(o.prims) do d = math.min(d, dist_to(q, x, y)) end
  return d
end

-- the parameter of the nearest of the samples S (taken at a + (b - a) i / (#S - 1), or
-- i / #S for a periodic curve) to each point of pts, through a grid of cells of size h
local function nearest_params(C, S, pts, h)
  local grid, xs, ys = {}, {}, {}
  for i = 1, #S do
    local x, y = S:get(i)
    xs[i], ys[i] = x, y
    local key = math.floor(x / h) * 1048576 + math.floor(y / h)
    local l = grid[key]
    if not l then l = {}; grid[key] = l end
    l[#l + 1] = i
  end
  local a, b = C:domain()
  local per = C:is_periodic()
  local u = {}
  for k, p in ipairs(pts) do
    local cx, cy, best, bi, r = math.floor(p[1] / h), math.floor(p[2] / h), math.huge, 1, 0
    while bi == 1 and best == math.huge or r <= 1 do
      for dx = -r, r do
        for dy = -r, r do
          if math.max(math.abs(dx), math.abs(dy)) == r then
            for _, i in ipairs(grid[(cx + dx) * 1048576 + cy + dy] or {}) do
              local d = (xs[i] - p[1]) ^ 2 + (ys[i] - p[2]) ^ 2
              if d < best then best, bi = d, i end
            end
          end
        end
      end
      r = r + 1
      if r > 4096 then break end
    end
    u[k] = a + (b - a) * (bi - 1) / (per and #S or (#S - 1))
    -- and the distance to the sampled polyline's two edges at that sample (exact where
    -- the curve is straight, where Newton may stall at a corner of the curve)
    local e = math.huge
    for _, j in ipairs { bi - 1, bi + 1 } do
      local jj = per and (j - 1) % #S + 1 or math.min(math.max(j, 1), #S)
      e = math.min(e, dist_to(line({ xs[bi], ys[bi] }, { xs[jj], ys[jj] }), p[1], p[2]))
    end
    u[#pts + k] = e
  end
  return u
end

-- Hausdorff distance between curve C and outline o: from k samples of C to o (exact
-- distances), and from points along o (each primitive cut into `dense` parts) to C
-- (Newton from the nearest of k samples of C: the closest point of C itself).
function M.hausdorff(bs, C, o, k, dense)
  k = k or 4000
  local S, h = C:sample(k), 0
  for i = 1, #S do
    local x, y = S:get(i)
    h = math.max(h, M.distance(o, x, y))
  end
  local pts = {}
  for _, q in ipairs(o.prims) do
    for j = 0, (dense or 200) do pts[#pts + 1] = at(q, j / (dense or 200)) end
  end
  -- Newton from the nearest sample and from its two neighbours (a foot across a corner
  -- of C stalls at the corner): the least of the three distances
  local u0 = nearest_params(C, S, pts, M.size(o) / 128)
  local a, b = C:domain()
  local step, Q, best = (b - a) / #S, bs.points.new(pts), {}
  for i = 1, #pts do best[i] = u0[#pts + i]; u0[#pts + i] = nil end
  for _, off in ipairs { -1, 0, 1 } do
    local u = {}
    for i = 1, #pts do local x = u0[i]; u[i] = math.min(math.max(x + off * step, a), b) end
    local _, d = C:project(Q, bs.vector.new(u), 30)
    for i = 1, #pts do best[i] = math.min(best[i] or math.huge, d:get(i)) end
  end
  for i = 1, #pts do h = math.max(h, best[i]) end
  return h
end

-- A sweep case's result C against the issue's floor: its Hausdorff distance to the true
-- outline over 3 sigma + 1e-3 of the size (within when at most 1).
function M.floor_ratio(bs, C, c)
  return M.hausdorff(bs, C, c.o, 2000, 60) / (3 * c.sigma + 1e-3 * c.size)
end

M.tangent = tangent
M.length = length
-- The turns (degrees) of the curve C of rep.pieces at its tangent (G1) joins between two
-- primitives (lines, arcs): the angle between C's derivatives just before and just after
-- each such join, and whether the pieces' own tangents there (prev.t_end, p.t_start) run
-- the same way. Free runs are left out (their end tangents are their neighbours' by
-- construction). Returns the largest turn, how many exceed `limit` degrees, how many
-- joins, and how many whose pieces' tangents oppose each other (a cusp called tangent).
function M.tangent_kinks(C, rep, limit)
  local worst, over, joins, opposed = 0, 0, 0, 0
  local P = rep.pieces or {}
  local a, b = C:domain()
  local function unit(x, y) local l = math.sqrt(x * x + y * y); return x / l, y / l end
  for i, p in ipairs(P) do
    local prev = P[(i - 2) % #P + 1]
    if p.join == "tangent" and #P > 1 and (i > 1 or rep.closed) and p.kind ~= "free"
       and prev.kind ~= "free" then
      local t, e = a + (b - a) * p.range[1], 1e-9 * (b - a)
      local t0 = t - e < a and t - e + (b - a) or t - e
      local x1, y1 = unit(C:deriv(t0))
      local x2, y2 = unit(C:deriv(t + e))
      local turn = math.deg(math.atan(math.abs(x1 * y2 - y1 * x2), x1 * x2 + y1 * y2))
      joins, worst = joins + 1, math.max(worst, turn)
      if turn > limit then over = over + 1 end
      if prev.t_end[1] * p.t_start[1] + prev.t_end[2] * p.t_start[2] <= 0 then opposed = opposed + 1 end
    end
  end
  return worst, over, joins, opposed
end


-- }======================================================================

-- {======================================================================
-- Where a corner may be found: the true corners, and the vertex of every arc shorter than
-- the sampling's step h (the issue: "a fillet wider than the local spacing is not a
-- corner"; one narrower, sampled once or not at all, may be one), where the lines tangent
-- at its ends meet; likewise an arc whose vertex is within 3 sigma of it (r (1/cos(sweep/2)
-- - 1) <= 3 sigma: at that noise the samples cannot tell the fillet from its corner).
function M.corner_places(o, h, sigma)
  local at = {}
  for _, v in ipairs(o.corners) do at[#at + 1] = v end
  for _, q in ipairs(o.prims) do
    local sag = q.kind == "arc" and q.r * (1 / math.cos(q.sweep / 2) - 1)
    if q.kind == "arc" and (q.r * math.abs(q.sweep) < h or sag <= 3 * (sigma or 0))
       and math.abs(q.sweep) < 0.9 * math.pi then
      local mid, d = q.a0 + q.sweep / 2, q.r / math.cos(q.sweep / 2)
      at[#at + 1] = { q.c[1] + d * math.cos(mid), q.c[2] + d * math.sin(mid) }
    end
  end
  return at
end

-- the largest step between consecutive samples (the closing step included, unless `open`)
function M.spacing(pts, open)
  local h = open and 0 or M.dist(pts[#pts], pts[1])
  for i = 2, #pts do h = math.max(h, M.dist(pts[i], pts[i - 1])) end
  return h
end

-- the true arc of outline o whose centre is nearest to `centre`, and how far that is
function M.true_arc(o, centre)
  local best, tr = math.huge, nil
  for _, q in ipairs(o.prims) do
    if q.kind == "arc" and M.dist(q.c, centre) < best then best, tr = M.dist(q.c, centre), q end
  end
  return tr, best
end

-- The issue's checks of the pieces of outline o read off samples pts (rep.pieces, or nil
-- for the smooth path): {corners = n, corners_ok = how many within the largest step of a
-- place a corner may be (corner_places), radii = arcs, radii_ok = how many within 2% of the
-- radius of the true arc whose centre is nearest, radii_fixed = arcs whose radius_se is at
-- most 1% of the radius, radii_fixed_ok = of those within 2%, radii_uncertain_ok = of the
-- others within 2% or 3 radius_se, true_arcs = the outline's arcs, true_arcs_ok = of those,
-- how many an arc piece reads within 2% (a fillet read as a corner is none: the share of
-- arcs found within 2% counts only the arcs found, and falls when more are found)}.
function M.features_found(o, pts, pieces)
  local r, hs = { corners = 0, corners_ok = 0, radii = 0, radii_ok = 0, radii_fixed = 0,
                  radii_fixed_ok = 0, radii_uncertain_ok = 0, true_arcs = 0, true_arcs_ok = 0 },
                M.spacing(pts)
  local read = {} -- the true arcs read within 2%

  local places = M.corner_places(o, hs)
  for _, p in ipairs(pieces or {}) do
    if p.join == "corner" then
      local best = math.huge
      for _, v in ipairs(places) do best = math.min(best, M.dist(v, p.start)) end
      r.corners = r.corners + 1
      if best <= hs then r.corners_ok = r.corners_ok + 1 end
    end
    if p.kind == "arc" then
      local tr = M.true_arc(o, p.centre)
      local err, lim = tr and math.abs(p.radius - tr.r) or math.huge, tr and 0.02 * tr.r or 0
      r.radii = r.radii + 1
      if err <= lim then r.radii_ok, read[tr] = r.radii_ok + 1, true end
      -- where the samples fix the radius to 1% (radius_se), within 2%; elsewhere within
      -- what radius_se says (3 of it)
      if (p.radius_se or math.huge) <= 0.01 * p.radius then
        r.radii_fixed = r.radii_fixed + 1
        if err <= lim then r.radii_fixed_ok = r.radii_fixed_ok + 1 end
      elseif err <= math.max(lim, 3 * p.radius_se) then
        r.radii_uncertain_ok = r.radii_uncertain_ok + 1
      end
    end
  end
  for _, q in ipairs(o.prims) do
    if q.kind == "arc" then
      r.true_arcs = r.true_arcs + 1
      if read[q] then r.true_arcs_ok = r.true_arcs_ok + 1 end
    end
  end
  return r
end

-- The sweep of sparse and noisy sections
-- =======================================================================

-- The sweep of sparse and noisy sections (issue 14: test_sharp_noisy.lua, and
-- tests/bench/sweep_sharp.lua to measure a change to it): every outline, in the order of
-- names() (or those of opts.names), x `pers` samples per side x noise `rels` of its size x
-- even and uneven samples (opts.unevens: {false, true}) x `draws` draws (1), each section
-- with its own seed: opts.seed(k, per, j, d) of the outline's place k in names(), the
-- noise's place j and the draw d (1000 k + 10 per + j unless given). An iterator of cases
-- {name, o, per, rel, uneven, draw, seed, sigma (absolute), size, pts}; with no opts the
-- issue's 390 sections:
--   for c in shapes.sweep_cases() do ... end
--   for c in shapes.sweep_cases { pers = { 4, 6 }, rels = { 1e-2 }, seed = f } do ... end
-- With opts.thin, in the sanitizer build (BSFIT_SANITIZED set by CMake), every
-- THIN_SANITIZED-th case only (M.thinned is then true): the sanitizers look for memory and
-- undefined behaviour, which a third of a sweep exercises as well as all of it, at a third
-- of the run; a test holds the third to floors of its own, measured (when M.thinned).
local THIN_SANITIZED = 3
M.thinned = require("tap").thinned
function M.sweep_cases(opts)
  opts = opts or {}
  local every, count = (opts.thin and M.thinned) and THIN_SANITIZED or 1, 0
  local pers, rels = opts.pers or { 3, 4, 5, 6, 10 }, opts.rels or { 1e-4, 1e-3, 3e-3 }
  local unevens, draws = opts.unevens or { false, true }, opts.draws or 1
  local seed = opts.seed or function(k, per, j) return 1000 * k + 10 * per + j end
  local wanted = nil
  if opts.names then
    wanted = {}
    for _, name in ipairs(opts.names) do wanted[name] = true end
  end
  local all = M.all()
  local function yield_draws(k, name, per, j, rel, uneven)
    local o = all[name]
    local size = M.size(o)
    for d = 1, draws do
      local c = { name = name, o = o, per = per, rel = rel, uneven = uneven, draw = d,
                  seed = seed(k, per, j, d), sigma = rel * size, size = size }
      count = count + 1
      if count % every == 0 then
        c.pts = M.sample(o, per, { sigma = c.sigma, seed = c.seed, uneven = uneven })
        coroutine.yield(c)
      end
    end
  end
  return coroutine.wrap(function()
    for k, name in ipairs(M.names()) do
      if not wanted or wanted[name] then
        for _, per in ipairs(pers) do
          for j, rel in ipairs(rels) do
            for _, uneven in ipairs(unevens) do yield_draws(k, name, per, j, rel, uneven) end
          end
        end
      end
    end
  end)
end

-- }======================================================================

-- {======================================================================
-- Random polygons (held-out families of their own: notched, filleted, chamfered)
-- =======================================================================

-- 4 to 7 vertices round a circle of radius 10, counter-clockwise, each within its own
-- sector (the polygon is simple)
function M.random_vertices(uniform)
  local n, v = 4 + math.floor(4 * uniform()), {}
  local a0 = 2 * pi * uniform()
  for k = 0, n - 1 do
    local a = a0 + 2 * pi * (k + 0.25 + 0.5 * uniform()) / n
    v[#v + 1] = { 10 * math.cos(a), 10 * math.sin(a) }
  end
  return v
end

-- the closed polygon through w: its outline in this module's form, every vertex a corner
function M.polygon(w)
  local o = { prims = {}, corners = {} }
  for i = 1, #w do
    o.prims[i] = line(w[i], w[i % #w + 1])
    o.corners[i] = w[i]
  end
  return o
end

-- count sections of generate(uniform) -> outline, sigma, per, extra, each sampled once
-- (evenly or unevenly at random; the k-th with noise seed sample_base + k, sample_base
-- seed unless given): {o, sigma, per, pts, size, extra}
function M.random_sections(seed, count, generate, sample_base)
  local uniform = M.rng(seed)
  local k = 0
  sample_base = sample_base or seed
  return function()
    k = k + 1
    if k > count then return nil end
    local o, sigma, per, extra = generate(uniform)
    local pts = M.sample(o, per, { seed = sample_base + k, sigma = sigma, uneven = uniform() < 0.5 })
    return { o = o, sigma = sigma, per = per, pts = pts, size = M.size(o), extra = extra }
  end
end

-- sections through auto: how many of them, and how many within the issue's floor (3 sigma
-- + 1e-3 of the size); T.eq holds every one free of crossings
function M.auto_within(T, bs, auto, sections)
  local n, within = 0, 0
  for c in sections do
    local C, rep = auto.run(bs.points.new(c.pts))
    n = n + 1
    if M.floor_ratio(bs, C, c) <= 1 then within = within + 1 end
    T.eq(rep.crossings, 0, "crossings")
  end
  return n, within
end

-- {======================================================================
-- Checks of bs.geom.segment's pieces
-- =======================================================================

-- The lines of pieces (bs.geom.segment's) that do not run from their start to their end
-- along their reported tangent (sin above 1e-9, backwards, or t_end other than t_start):
-- how many lines there are, those off ({i, sin, cos} each) and the largest sin.
function M.lines_off_tangent(pieces)
  local lines, off, worst = 0, {}, 0
  for i, p in ipairs(pieces) do
    local dx, dy = p["end"][1] - p.start[1], p["end"][2] - p.start[2]
    local l = math.sqrt(dx * dx + dy * dy)
    if p.kind == "line" and l > 0 then
      local sin = math.abs(dx * p.t_start[2] - dy * p.t_start[1]) / l
      local cos = (dx * p.t_start[1] + dy * p.t_start[2]) / l
      lines, worst = lines + 1, math.max(worst, sin)
      if sin > 1e-9 or cos <= 0 or p.t_end[1] ~= p.t_start[1] or p.t_end[2] ~= p.t_start[2] then
        off[#off + 1] = { i = i, sin = sin, cos = cos }
      end
    end
  end
  return lines, off, worst
end

-- the pieces of points P (a Points) segmented at the noise they show
-- (bs.geom.segment_sigma); {} where it reads none
function M.segment_at_own_noise(bs, P, closed)
  local s = bs.geom.segment_sigma(P, { closed = closed })
  return s > 0 and bs.geom.segment(P, { closed = closed, sigma = s }) or {}
end

-- an open part of a closed section's samples pts: a quarter to a half of them dropped,
-- from a random place
function M.open_part(pts, uniform)
  local m, first = #pts, 1 + math.floor(#pts * uniform())
  local drop, part = math.floor(m * (0.25 + 0.25 * uniform())), {}
  for j = 0, m - drop - 1 do part[#part + 1] = pts[(first + drop + j - 1) % m + 1] end
  return part
end

-- }======================================================================

return M
