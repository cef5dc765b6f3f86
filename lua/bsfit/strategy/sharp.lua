-- lua/bsfit/strategy/sharp.lua
-- The one curve of a section made of lines, circular arcs and free-form runs (issue 14),
-- used by the `auto` strategy's `segment` and `assemble` steps:
--
--   local sharp = require "bsfit.strategy.sharp"
--   local pieces = bs.geom.segment(P, {closed = true})      -- lines, arcs, free runs
--   local C = sharp.assemble(P, pieces, {closed = true, sigma = 0, weights = w})
--
-- Lines become cubics with collinear control points, arcs exact rational cubics
-- (bs.curve.arc; at a tangent join held to their neighbour's tangent, and between two
-- tangent lines drawn as their fillet), free runs a least-squares cubic (bs.fitter) whose
-- ends are fixed at the neighbouring primitives' ends with their drawn tangents (G1);
-- bs.curve.join makes them
-- one curve with knots of multiplicity 3 at the joins. On exact data (sigma 0) a free
-- run is interpolated (the clamped cubic spline with end tangents: knots at its
-- samples' parameters); on noisy data its count grows until it explains the samples as
-- noise would.

local bs = require "bsfit"

local M = {}

local function dist(a, b) return math.sqrt((a[1] - b[1]) ^ 2 + (a[2] - b[2]) ^ 2) end

-- the samples of a piece, as a Lua array of {x, y}, and their weights; those whose index
-- is a key of `skip` left out
local function piece_samples(P, p, w, skip)
  local m, q, ww = #P, {}, {}
  for k = 0, p.count - 1 do
    local i = (p.first - 1 + k) % m + 1
    if not (skip and skip[i]) then
      q[#q + 1] = { P:get(i) }
      ww[#ww + 1] = w and w[i] or 1
    end
  end
  return q, ww
end

-- the RMS and largest distance of the points pts to the circle of centre c and radius r
-- (rms and max when there are none)
local function circle_residuals(pts, c, r, rms, max)
  if #pts == 0 then return rms, max end
  local q2, worst = 0, 0
  for _, x in ipairs(pts) do
    local d = math.abs(dist(x, c) - r)
    q2, worst = q2 + d * d, math.max(worst, d)
  end
  return math.sqrt(q2 / #pts), worst
end

-- chord parameters in [0, 1] of the polyline pts; its length
local function chord_params(pts)
  local u, acc = { 0 }, 0
  for i = 2, #pts do acc = acc + dist(pts[i], pts[i - 1]); u[i] = acc end
  if acc <= 0 then return nil, 0 end
  for i = 2, #pts do u[i] = u[i] / acc end
  u[#pts] = 1
  return u, acc
end

-- the cubic from a to b leaving a along ta and reaching b along tb, no data between
local function hermite(a, b, ta, tb)
  local L = dist(a, b) / 3
  return bs.curve.new { degree = 3, control_points = {
    a, { a[1] + L * ta[1], a[2] + L * ta[2] }, { b[1] - L * tb[1], b[2] - L * tb[2] }, b } }
end

-- knots for n control points over the samples' parameters u[3..#u-2] (u[1] = u[2] and
-- u[#u-1] = u[#u] are the fixed ends): at the parameters themselves when n = their
-- number + 4 (interpolation), else at their quantiles
local function quantile_knots(u, n)
  local inner, kv = {}, { 0, 0, 0, 0 }
  for i = 3, #u - 2 do -- strictly inside (0, 1) and increasing: a sample an ulp from an end
    if u[i] > (inner[#inner] or 0) and u[i] < 1 then inner[#inner + 1] = u[i] end
  end
  if n >= #inner + 4 then
    for _, x in ipairs(inner) do kv[#kv + 1] = x end
    for _ = 1, 4 do kv[#kv + 1] = 1 end
    return bs.knots.new { degree = 3, values = kv }
  end
  for j = 1, n - 4 do
    local x = j * #inner / (n - 3)
    local i = math.floor(x)
    local f = x - i
    local lo = inner[math.max(i, 1)] or 0
    local hi = inner[math.min(i + 1, #inner)] or 1
    kv[#kv + 1] = lo + f * (hi - lo)
  end
  for _ = 1, 4 do kv[#kv + 1] = 1 end
  return bs.knots.new { degree = 3, values = kv }
end

-- The length a noisy free run's end tangents are given (pts: its ends and samples, L
-- their polyline's length). Noise lengthens every step (a step of true length d between
-- samples of noise sigma in each coordinate has a mean square d^2 + 4 sigma^2): where
-- the samples are closer than the noise, L is mostly noise, and tangents that long made
-- the cubic overshoot its ends into a small loop (a fillet read as lines and softened
-- into a bend of two samples at noise 1e-3: the pieces' curve crossed itself, and the
-- section lost its corners to the smooth path). Each step counts what is left of it
-- after the noise, and the whole no less than 1.5 chords (a bend no tighter than a half
-- circle is under 1.6 chords long), nor more than L.
local function free_length(pts, L, sigma)
  if sigma <= 0 then return L end
  local denoised = 0
  for i = 2, #pts do
    denoised = denoised + math.sqrt(math.max(dist(pts[i], pts[i - 1]) ^ 2 - 4 * sigma ^ 2, 0))
  end
  return math.min(L, math.max(denoised, 1.5 * dist(pts[1], pts[#pts])))
end

-- Whether a noisy free run's fit explains its c samples as noise would: its squared
-- residuals (rss, in sigma^2) within the mean plus three standard deviations of a
-- chi-square of c degrees of freedom, or 1.44 c (an RMS of 1.2 sigma) when that is more.
-- The RMS alone refused a run of 2 samples one time in four where the cubic was right,
-- and the next count interpolated a sample 2.5 sigma off: a spike, then a loop.
local function explains_as_noise(rss, c)
  c = math.max(c, 1)
  return rss <= math.max(1.44 * c, c + 3 * math.sqrt(2 * c))
end

-- One free run: fixed ends at the pieces' ends, tangents of the neighbours (G1).
-- Exact data: interpolated; noisy: the fewest control points that explain its samples as
-- noise would (explains_as_noise), the tangents no longer than free_length.
local function free_run(P, p, o)
  local inner, ww = piece_samples(P, p, o.weights, o.skip)
  local a, b = p.start, p["end"]
  if #inner == 0 then return hermite(a, b, p.t_start, p.t_end) end
  -- repeated samples (a zero chord) would repeat a parameter, and an interpolating knot
  -- vector would then hold a knot p + 2 times: each is kept once
  local pts, w = { a, a }, { 1, 1 }
  for i, q in ipairs(inner) do
    if dist(q, pts[#pts]) > 0 and dist(q, b) > 0 then pts[#pts + 1] = q; w[#w + 1] = ww[i] end
  end
  if #pts == 2 then return hermite(a, b, p.t_start, p.t_end) end
  pts[#pts + 1], pts[#pts + 2] = b, b
  w[#w + 1], w[#w + 2] = 1, 1
  local u, L = chord_params(pts)
  if not u then return hermite(a, b, p.t_start, p.t_end) end
  local Q, U, W = bs.points.new(pts), bs.vector.new(u), bs.vector.new(w)
  L = free_length(pts, L, o.sigma)
  local base = { degree = 3, fix_ends = true, solver = "auto",
                 tangent_start = { L * p.t_start[1], L * p.t_start[2] },
                 tangent_end = { L * p.t_end[1], L * p.t_end[2] } }
  local c = #pts - 4
  local counts = {}
  if o.sigma <= 0 then counts = { c + 4 }
  else
    local n = 4
    while n < c + 4 do counts[#counts + 1] = n; n = math.max(n + 1, math.floor(n * 1.4)) end
    counts[#counts + 1] = c + 4
  end
  local best
  for _, n in ipairs(counts) do
    base.knots = quantile_knots(u, n)
    local C, rep = bs.fitter(base):fit(Q, U, W)
    if C then
      best = C
      if o.sigma > 0 and explains_as_noise(rep.rms ^ 2 * #pts / o.sigma ^ 2, c) then break end
    end
  end
  return best or hermite(a, b, p.t_start, p.t_end)
end

-- The circle through a and b leaving a along the unit tangent t (or, with at_end,
-- reaching b along it): its centre; nil when b lies on the tangent's line (no such circle)
-- or the circle runs the other way round than `sweep`, the model's (> 0 counterclockwise).
local function tangent_circle(a, b, t, at_end, sweep)
  local q, x = at_end and b or a, at_end and a or b
  local n = { -t[2], t[1] } -- the left normal: the centre of a counterclockwise circle
  local dx, dy = x[1] - q[1], x[2] - q[2]
  local h = n[1] * dx + n[2] * dy
  if not (math.abs(h) > 1e-12 * math.sqrt(dx * dx + dy * dy)) then return nil end
  local s = (dx * dx + dy * dy) / (2 * h) -- |x - q - s n| = |s|
  if (s > 0) ~= (sweep > 0) then return nil end
  return { q[1] + s * n[1], q[2] + s * n[2] }
end

-- the signed angle from a to b around c
local function angle(c, a, b)
  local ax, ay, bx, by = a[1] - c[1], a[2] - c[2], b[1] - c[1], b[2] - c[2]
  return math.atan(ax * by - ay * bx, ax * bx + ay * by)
end

-- the turn from a to b round c in the direction of the model's sweep (a whole turn when
-- they coincide)
local function sweep_round(p, a, b, c)
  if a[1] == b[1] and a[2] == b[2] then return p.sweep end
  local sweep = angle(c, a, b)
  if (sweep > 0) ~= (p.sweep > 0) or sweep == 0 then
    sweep = sweep + (p.sweep > 0 and 2 or -2) * math.pi
  end
  return sweep
end

-- How far the arc from a to b round centre c (in the model's direction) strays from the
-- model's circle: the largest distance to it of 15 points inside the arc.
local function off_model(p, a, b, c)
  local r, a0, sweep, worst = dist(a, c), math.atan(a[2] - c[2], a[1] - c[1]), sweep_round(p, a, b, c), 0
  for k = 1, 15 do
    local t = a0 + sweep * k / 16
    local x = { c[1] + r * math.cos(t), c[2] + r * math.sin(t) }
    worst = math.max(worst, math.abs(dist(x, p.centre) - p.radius))
  end
  return worst
end

-- The centre of the arc drawn from a to b: on the ends' perpendicular bisector, so that the
-- arc passes through both exactly (under noise a join lies within the tolerance of the
-- fitted circle, not on it; on exact data nothing moves). Where the arc meets a neighbour
-- tangentially (t_start, t_end: the neighbour's drawn tangent there, or nil) it is held on
-- that end's normal too, so that the join is G1 as drawn (the bisector alone turned the
-- arc's tangent at a tangent join by up to 3 degrees, on noisy letters), when that keeps
-- the arc as near its model's circle as the bisector's, within `slack`: `sigma` where a
-- line holds it, none where an arc does (a chain of tangent arcs, each held by the one
-- before, drifts from its samples: an airfoil read as 5 arcs at noise 1e-3 went from
-- 0.96 to 1.1 times the floor with sigma there). Only one end can be held so; the start
-- is, when both ask.
local function arc_centre(p, t_start, t_end, slack)
  local a, b, c = p.start, p["end"], p.centre
  local mx, my, dx, dy = (a[1] + b[1]) / 2, (a[2] + b[2]) / 2, b[1] - a[1], b[2] - a[2]
  local l2 = dx * dx + dy * dy
  if l2 == 0 then return c end
  local t = ((c[1] - mx) * dx + (c[2] - my) * dy) / l2
  c = { c[1] - t * dx, c[2] - t * dy }
  local held = t_start and tangent_circle(a, b, t_start, false, p.sweep)
      or t_end and tangent_circle(a, b, t_end, true, p.sweep)
  if not held then return c end
  slack = math.max(slack, 1e-9 * p.radius)
  if off_model(p, a, b, held) <= off_model(p, a, b, c) + slack then
    return held
  end
  return c
end

-- The curve of an arc piece and its length (nil when its model is degenerate: repeated
-- samples can give a whole-circle arc whose centre is its end; a free run then fits them).
-- The circle drawn is kept in p.drawn (M.as_drawn reports it).
local function arc_curve(p, t_start, t_end, slack)
  local a, b = p.start, p["end"]
  local c = arc_centre(p, t_start, t_end, slack)
  local r = dist(a, c)
  local a0, sweep = math.atan(a[2] - c[2], a[1] - c[1]), sweep_round(p, a, b, c)
  if not (r > 0 and r < math.huge and math.abs(sweep) <= 2 * math.pi) then return nil end
  p.drawn = { centre = c, radius = r, sweep = sweep }
  return bs.curve.arc { centre = c, radius = r, start = a0, sweep = sweep }, r * math.abs(sweep)
end

local function unit_of(v)
  local l = math.sqrt(v[1] * v[1] + v[2] * v[2])
  return l > 0 and { v[1] / l, v[2] / l } or nil
end

-- The fillet of arc piece p between lines A (before) and B (after) that it meets
-- tangentially: the circle tangent to both lines nearest its model (the centre on the
-- line of points as far from both, on the model centre's sides, the model centre's
-- projection onto it) and its tangent points. Returns centre, radius, the point on A, the
-- point on B; nil when the lines are parallel the same way or a tangent point falls behind
-- its line's other end.
local function fillet_between(A, p, B)
  local function normal(L) -- of the line as drawn (its ends may lie off its model's line)
    local dx, dy = L["end"][1] - L.start[1], L["end"][2] - L.start[2]
    local l = math.sqrt(dx * dx + dy * dy)
    return { -dy / l, dx / l }, { dx / l, dy / l }
  end
  local function side(n, L, x) return n[1] * (x[1] - L.start[1]) + n[2] * (x[2] - L.start[2]) end
  local na, ta = normal(A)
  local nb, tb = normal(B)
  local c = p.centre
  local sa, sb = side(na, A, c) < 0 and -1 or 1, side(nb, B, c) < 0 and -1 or 1
  -- sa side_A(x) = sb side_B(x): g . x = h
  local g = { sa * na[1] - sb * nb[1], sa * na[2] - sb * nb[2] }
  local h = sa * (na[1] * A.start[1] + na[2] * A.start[2]) - sb * (nb[1] * B.start[1] + nb[2] * B.start[2])
  local g2 = g[1] * g[1] + g[2] * g[2]
  if not (g2 > 1e-24) then return nil end
  local k = (g[1] * c[1] + g[2] * c[2] - h) / g2
  local cc = { c[1] - k * g[1], c[2] - k * g[2] }
  local r = sa * side(na, A, cc)
  if not (r > 0) then return nil end
  local fa = { cc[1] - sa * r * na[1], cc[2] - sa * r * na[2] }
  local fb = { cc[1] - sb * r * nb[1], cc[2] - sb * r * nb[2] }
  if (fa[1] - A.start[1]) * ta[1] + (fa[2] - A.start[2]) * ta[2] <= 0 then return nil end
  if (B["end"][1] - fb[1]) * tb[1] + (B["end"][2] - fb[2]) * tb[2] <= 0 then return nil end
  return cc, r, fa, fb
end

-- Arcs that meet lines tangentially at both ends are drawn as their fillets (G1 at both
-- ends: an arc held at one end only met the other line at up to 0.9 degrees, on dense
-- noisy filleted polygons) when that keeps them within `sigma` as near their model's
-- circle as an arc through their ends would be; the lines' ends and the arc's ends,
-- centre and radius are then the fillet's, and its rms and max its samples' distances to it.
local function fillets(P, pieces, o)
  local n = #pieces
  if n < 3 then return end
  for i, p in ipairs(pieces) do
    local A, B = pieces[(i - 2) % n + 1], pieces[i % n + 1]
    if p.kind == "arc" and A.kind == "line" and B.kind == "line" and p.join == "tangent"
        and B.join == "tangent" and (o.closed or (i > 1 and i < n)) then
      local cc, r, fa, fb = fillet_between(A, p, B)
      if cc then
        local sweep = sweep_round(p, fa, fb, cc)
        local through = arc_centre(p, nil, nil, 0)
        local slack = math.max(o.sigma, 1e-9 * p.radius)
        if math.abs(sweep) < 2 * math.pi and
            off_model(p, fa, fb, cc) <= off_model(p, p.start, p["end"], through) + slack then
          A["end"], p.start, p["end"], B.start = fa, fa, fb, fb
          p.centre, p.radius, p.sweep = cc, r, sweep
          p.rms, p.max = circle_residuals(piece_samples(P, p), cc, r, p.rms, p.max)
        end
      end
    end
  end
end

-- The unit tangents of a drawn part at its ends.
local function part_tangents(C)
  local a, b = C:domain()
  return unit_of { C:deriv(a) }, unit_of { C:deriv(b) }
end

-- The order the pieces are drawn in: lines first (their ends fix them), then the arcs
-- along the list from one that no tangent arc precedes (a chain of tangent arcs is drawn
-- from its start, each arc taking the tangent the one before it was drawn with), then the
-- free runs (their end tangents are their neighbours' as drawn).
local function drawing_order(pieces, closed)
  local n, order = #pieces, {}
  local function chained(i) -- an arc that a tangent arc before it holds
    local prev = pieces[(i - 2) % n + 1]
    return pieces[i].join == "tangent" and prev.kind == "arc" and (i > 1 or closed) and n > 1
  end
  local first = 1
  for i = 1, n do
    if not (pieces[i].kind == "arc" and chained(i)) then first = i; break end
  end
  for _, kind in ipairs { "line", "arc", "free" } do
    for k = 0, n - 1 do
      local i = (first - 1 + k) % n + 1
      if pieces[i].kind == kind then order[#order + 1] = i end
    end
  end
  return order
end

-- Draws every piece (see drawing_order): parts[i], lens[i], and each part's end tangents.
local function draw_pieces(P, pieces, o)
  local n, parts, lens, ts, te = #pieces, {}, {}, {}, {}
  fillets(P, pieces, o)
  local function neighbour_tangent(i, at_start) -- a drawn primitive's tangent at the join
    local j = at_start and (i - 2) % n + 1 or i % n + 1
    local p = pieces[i]
    local join = at_start and p.join or pieces[j].join
    if join ~= "tangent" or n < 2 or pieces[j].kind == "free" then return nil end
    if not o.closed and (at_start and i == 1 or not at_start and i == n) then return nil end
    if not parts[j] then return nil end
    return at_start and te[j] or ts[j]
  end
  for _, i in ipairs(drawing_order(pieces, o.closed)) do
    local p = pieces[i]
    if p.kind == "line" then
      parts[i], lens[i] = bs.curve.line(p.start, p["end"]), dist(p.start, p["end"])
    elseif p.kind == "arc" then
      local t0, t1 = neighbour_tangent(i, true), neighbour_tangent(i, false)
      local holder = t0 and pieces[(i - 2) % n + 1] or t1 and pieces[i % n + 1]
      parts[i], lens[i] = arc_curve(p, t0, t1, holder and holder.kind == "line" and o.sigma or 0)
    end
    if not parts[i] then
      local q = {}
      for k, v in pairs(p) do q[k] = v end
      q.t_start = neighbour_tangent(i, true) or p.t_start
      q.t_end = neighbour_tangent(i, false) or p.t_end
      parts[i] = free_run(P, q, o)
      lens[i] = math.max(parts[i]:length(), 1e-300)
    end
    ts[i], te[i] = part_tangents(parts[i])
  end
  return parts, lens
end

-- Why pieces cannot be made into one curve (nil when they can): a line or an arc of zero
-- length between two joins, or an arc that goes all the way round beside other pieces (a
-- segmentation of a noisy blob can close one arc on itself and leave its neighbour nothing).
function M.degenerate(pieces)
  local scale = 0
  for _, p in ipairs(pieces) do scale = math.max(scale, math.abs(p.start[1]), math.abs(p.start[2])) end
  for i, p in ipairs(pieces) do
    local len = p.kind == "arc" and p.radius * math.abs(p.sweep) or dist(p.start, p["end"])
    if p.kind ~= "free" and not (len > 1e-12 * scale) and not (#pieces == 1 and p.kind == "arc") then
      return ("piece %d (%s) has no length"):format(i, p.kind)
    end
    if p.kind == "arc" and #pieces > 1 and math.abs(p.sweep) >= 2 * math.pi - 1e-9 then
      return ("arc %d goes all the way round"):format(i)
    end
  end
  return nil
end

-- Does the segmentation of m samples carry features worth one curve of pieces? Lines
-- and arcs must hold at least half the samples: a short run that rounded data fits
-- by chance (4 samples of a cam's base circle, to 6 decimals) does not make a section
-- of lines and arcs.
-- A corner of less than SLIGHT_TURN degrees with an arc beside it, or that one smooth
-- curve explains better than the two models (its evidence below CHAIN_EVIDENCE, in units
-- of the tolerance over 4): arcs and short lines that follow a smooth curve, each within the
-- tolerance of its samples, and meet at a slight angle. On exact samples the tolerance (1e-10
-- of the size) keeps such runs short; samples written with a few decimals raise it to the
-- rounding (segment.c, decimal_floor), and 200 to 1000 samples of a cam, an ellipse or a star
-- written with 5 or 6 decimals were read as chains of arcs and lines meeting at corners of
-- 0.01 to 0.4 degrees (evidence -27 to 169). A polygon's exact corners, however slight, are
-- worth far more.
local SLIGHT_TURN, CHAIN_EVIDENCE = 1, 25
local function slight_corner(pieces)
  for i, p in ipairs(pieces) do
    local q = pieces[(i - 2) % #pieces + 1]
    if p.join == "corner" and p.turn and p.turn < SLIGHT_TURN and
       (p.kind == "arc" or q.kind == "arc" or (p.evidence or math.huge) < CHAIN_EVIDENCE) then
      return true
    end
  end
  return false
end

function M.has_features(pieces, m)
  if M.degenerate(pieces) or slight_corner(pieces) then return false end
  local held = 0
  for _, p in ipairs(pieces) do if p.kind ~= "free" then held = held + p.count end end
  return held >= 0.5 * m
end

-- Is the free piece pieces[i] of no samples (a bridge: the models of its neighbours do not
-- meet between them) the join of two lines that continue each other, their directions
-- within CONTINUES_TURN degrees (what noisy_pieces asks of a corner at least)? Such lines
-- are one side split where a sample lies past the tolerance, or a side too short to hold a
-- sample of its own, and the free piece, a short Hermite step, joins them. Elsewhere a
-- bridge means a model took samples of its neighbour (a line on the first samples of an arc).
local CONTINUES_TURN = 15
function M.continues(pieces, i)
  local a, b = pieces[(i - 2) % #pieces + 1], pieces[i % #pieces + 1]
  if a == b or a.kind ~= "line" or b.kind ~= "line" then return false end
  local c = a.t_end[1] * b.t_start[1] + a.t_end[2] * b.t_start[2]
  return c >= math.cos(math.rad(CONTINUES_TURN))
end

-- how far along piece p from x to y (points on or next to its model): an arc's radius
-- times the angle it turns from x to y in its own direction, else the chord
local function along(p, x, y)
  if p.kind ~= "arc" then return dist(x, y) end
  local a = angle(p.centre, x, y)
  if a * p.sweep < 0 then a = a + (p.sweep > 0 and 2 or -2) * math.pi end
  return p.radius * math.abs(a)
end

-- The pieces of a closed segmentation that hold the last sample and the first (one that
-- starts there): their indices, nil when either is missing.
local function closing_ends(m, pieces)
  local ia, ib
  for i, p in ipairs(pieces) do
    local last = p.first + p.count - 1
    if p.count > 0 and last >= m then ia = i end
    if p.count > 0 and (p.first == 1 or last > m) and (not ib or p.first == 1) then ib = i end
  end
  return ia, ib
end

-- The length of the stretch the pieces of a closed segmentation add between the last
-- sample and the first: along the piece that holds the last sample to its end, across any
-- bridges, along the piece that holds the first from its start (or, when one piece holds
-- both, along it from one to the other).
local function closing_length(P, pieces)
  local m, n = #P, #pieces
  local a, b = { P:get(m) }, { P:get(1) }
  local ia, ib = closing_ends(m, pieces)
  if not ia or not ib then return math.huge end
  if ia == ib then return along(pieces[ia], a, b) end
  local len, i = along(pieces[ia], a, pieces[ia]["end"]), ia % n + 1
  while i ~= ib do
    len, i = len + dist(pieces[i].start, pieces[i]["end"]), i % n + 1
  end
  return len + along(pieces[ib], pieces[ib].start, b)
end

-- The way the pieces of a closed segmentation go from the last sample to the first: the
-- last sample, the ends of the pieces between (each piece's end, round its model or
-- across a bridge: straight from join to join), the first sample. One piece holding both
-- samples: the chord between them.
function M.closing_path(P, pieces)
  local m, n = #P, #pieces
  local path = { { P:get(m) } }
  local ia, ib = closing_ends(m, pieces)
  if ia and ib and ia ~= ib then
    local i = ia
    while i ~= ib do
      path[#path + 1] = pieces[i]["end"]
      i = i % n + 1
    end
  end
  path[#path + 1] = { P:get(1) }
  return path
end

-- the longest step between the samples of piece p (of a section of m samples); in C, as
-- the closing pieces of a dense section hold most of its samples
local function piece_longest_step(P, m, p)
  if p.count < 2 then return 0 end
  if p.count == 2 then
    local x1, y1 = P:get(p.first)
    local x2, y2 = P:get(p.first % m + 1)
    return math.sqrt((x2 - x1) ^ 2 + (y2 - y1) ^ 2)
  end
  local last = p.first + p.count - 1
  local Q = last <= m and P:slice(p.first, last) or P:rotate(p.first):slice(1, p.count)
  return bs.geom.longest_step(Q, { closed = false })
end

-- Do the closing pieces close the section only over a stretch no sample saw? They run on
-- past both end samples, into the gap, farther than CLOSURE_UNSAMPLED times their own
-- longest step, or they are bridged there by a free run of no samples (their models do not
-- meet within reach: the curve would invent a smooth stretch across the gap), unless the
-- bridge joins lines that continue each other (one side split). A closed outline's closing
-- step spans what lies between two samples; pieces that run on that far close an outline
-- no sample saw (three sides of a quadrilateral closed as a triangle, or with a rounded
-- top). On 2800 held-out clean outlines, the closed ones ran on at most 1.2 times at the
-- nearer end, and open ones closed without a doubt went from 5 to 2 of 40; of 624 closed
-- sections of the sparse sweep (3 to 20 samples per side, noise 0 to 3e-3), one more is
-- said ambiguous (22), sampled unevenly along long sides.
local CLOSURE_UNSAMPLED = 1.5
function M.closure_unsampled(P, pieces)
  local m, n = #P, #pieces
  local ia, ib = closing_ends(m, pieces)
  if not ia or not ib or ia == ib then return false end
  local i = ia % n + 1
  while i ~= ib do
    if pieces[i].kind == "free" and pieces[i].count == 0 and not M.continues(pieces, i) then
      return true
    end
    i = i % n + 1
  end
  local A, B = pieces[ia], pieces[ib]
  local run_a = dist({ P:get(m) }, A["end"]) / piece_longest_step(P, m, A)
  local run_b = dist(B.start, { P:get(1) }) / piece_longest_step(P, m, B)
  return run_a > CLOSURE_UNSAMPLED and run_b > CLOSURE_UNSAMPLED
end

-- The pieces of a section segmented as closed, when lines and arcs hold it and meet across
-- the gap between its last and first samples (gap: their distance) without a detour: the
-- stretch they add there (closing_length) at most CLOSING_DETOUR gaps (the end sides of an
-- open run of an outline may meet, but far out; an exact arc of a third of a circle reads
-- as a whole circle), the gap no longer than three times the longest other step (an open
-- run's ends lie across its shape). Exact lines and arcs: returns the pieces and true. Else
-- lines and arcs within the noise they show themselves (bs.geom.segment_sigma) that hold
-- 90% of the samples, meet everywhere (a bridge only between lines that continue each
-- other: a side split where a sample lies past the tolerance) and do not close with a
-- free run. nil otherwise.
local CLOSING_DETOUR = 2
function M.closing_pieces(P, gap)
  local m = #P
  local longest, px, py = 0, P:get(1) -- 2D: no table per step (it runs on every sample)
  for i = 2, m do
    local x, y = P:get(i)
    longest, px, py = math.max(longest, math.sqrt((x - px) ^ 2 + (y - py) ^ 2)), x, y
  end
  if gap > 3 * longest then return nil end
  local pieces = bs.geom.segment(P, { closed = true })
  local exact = pieces and M.has_features(pieces, m)
  if not exact then
    local s = bs.geom.segment_sigma(P, { closed = true })
    if not (s and s > 0) then return nil end
    pieces = bs.geom.segment(P, { closed = true, sigma = s })
    local held = 0
    for _, p in ipairs(pieces or {}) do if p.kind ~= "free" then held = held + p.count end end
    if held < 0.9 * m then return nil end
  end
  for i, p in ipairs(pieces) do
    if p.kind == "free" and p.count == 0 and (exact or not M.continues(pieces, i)) then
      return nil
    end
    if p.first == 1 and p.kind == "free" and not exact then return nil end
  end
  if closing_length(P, pieces) > CLOSING_DETOUR * gap then return nil end
  return pieces, exact
end

-- A closed curve joined from pieces (clamped, its ends equal) in the periodic form
-- (the seam a knot of multiplicity 3), as the other strategies return closed curves.
local function periodic_of(C)
  -- a single piece (a whole circle: 4 control points) leaves 3 distinct ones, too few for
  -- a closed cubic: one more knot (exact) gives the period room
  if #C:control_points() < 5 then
    local a, b = C:domain()
    C = C:insert((a + b) / 2, 1)
  end
  local ctrl, kv, w = C:control_points():totable(), C:knots():totable(), C:weights()
  if w then w = w:totable() end
  local n = #ctrl
  local pts, ws, period = {}, w and {} or nil, { 0 }
  for i = 1, n - 1 do pts[i] = ctrl[i]; if ws then ws[i] = w[i] end end
  for i = 5, n do period[#period + 1] = kv[i] end -- the inner knots
  for _ = 1, 3 do period[#period + 1] = 1 end     -- the seam: C(0) = C(1) = P_1
  return bs.curve.new { degree = 3, periodic = true, control_points = pts, weights = ws,
                        knots = period }
end

-- The one curve of the pieces (see the head of this file). o: closed, sigma, weights (Lua
-- array or nil), skip (a set of sample indices no free run is fitted to: down-weighted
-- points, which a run of as many control points as samples would otherwise pass through).
-- Returns the curve and the parameter range of each piece.
function M.assemble(P, pieces, o)
  local parts, lens = draw_pieces(P, pieces, o)
  local total = 0
  for i = 1, #pieces do total = total + lens[i] end
  local C = bs.curve.join(parts, lens)
  local acc = 0
  for i, p in ipairs(pieces) do
    p.range = { acc / total, (acc + lens[i]) / total }
    acc = acc + lens[i]
  end
  pieces[#pieces].range[2] = 1
  if o.closed then C = periodic_of(C) end
  return C
end

-- the RMS and largest of piece p's samples' distances (distances: each sample's, a Lua
-- array; skip: indices left out), p's own when none is left
local function piece_residuals(P, p, distances, skip)
  local m, q2, worst, n = #P, 0, 0, 0
  local first, last = p.first, p.first + p.count - 1 -- 1-based, last up to 2 m (wrapped)
  local function add(a, b) -- samples a .. b, in range
    for i = a, b do
      if not (skip and skip[i]) then
        local d = distances[i]
        q2, n = q2 + d * d, n + 1
        if d > worst then worst = d end
      end
    end
  end
  add(first, math.min(last, m))
  if last > m then add(1, last - m) end
  if n == 0 then return p.rms, p.max end
  return math.sqrt(q2 / n), worst
end

-- The pieces as their curve draws them, for the report: copies in which an arc's centre,
-- radius and sweep are those of the arc drawn (under noise its ends lie within the
-- tolerance of its fitted circle, not on it, and the arc is drawn through them: its
-- centre moves along their bisector, by many sigma on a short arc; the fitted circle stays
-- in fit_centre and fit_radius), and every piece's rms and max are its samples' distances
-- to the curve, from `distances` (each sample's, a Lua array: sharp.distances of the
-- curve, the measure step's) when given (the segmentation's are to its models: a free run
-- has none, a bend made by M.soften had no rms at all, and an arc's model is not the arc
-- drawn). Pieces never drawn (the sharp.assemble that made the curve was not run on them)
-- keep their centre. skip: sample indices left out of rms and max (down-weighted points,
-- as in sharp.assemble's options).
function M.as_drawn(P, pieces, skip, distances)
  local out = {}
  for i, p in ipairs(pieces) do
    local q = {}
    for k, v in pairs(p) do q[k] = v end
    q.drawn = nil
    if p.kind == "arc" and p.drawn then
      local c = p.drawn.centre
      q.fit_centre, q.fit_radius = p.centre, p.radius
      q.centre, q.radius, q.sweep = { c[1], c[2] }, p.drawn.radius, p.drawn.sweep
    end
    if p.count > 0 and distances then q.rms, q.max = piece_residuals(P, p, distances, skip) end
    out[i] = q
  end
  return out
end

-- The distances of the samples to the curve of the pieces (a Vector): each sample's foot is
-- found by Newton from its place in its own piece's parameter range, so that it never has
-- to cross a corner (a foot search from a global start can stall at a C0 knot and report
-- the distance to the corner instead); the nearer of that and the global closest point
-- (bs.geom.piece_distances: the whole loop in C).
function M.distances(C, P, pieces)
  return bs.geom.piece_distances(C, P, pieces, 8)
end

-- A corner farther from the samples on either side of it than the longest step of the
-- section (two noisy sides meeting at a spike far out: a keyhole of 4 uneven samples per
-- side at noise 1e-2 had its last two sides meet 5 units below it) is not what the samples
-- show. Returns a message, or nil. (The longest step is the C kernel's: a loop in Lua
-- took 16 ms of a 10^5-sample section's 60.)
function M.far_corner(P, pieces)
  local m, longest = #P, bs.geom.longest_step(P)
  local function to(x, i) -- the distance from {x, y} to sample i
    local px, py = P:get(i)
    return math.sqrt((x[1] - px) ^ 2 + (x[2] - py) ^ 2)
  end
  for k, p in ipairs(pieces) do
    if p.join == "corner" then
      local d = math.min(to(p.start, p.first), to(p.start, (p.first - 2) % m + 1))
      if d > longest then return ("corner %d is %.3g from its samples (steps up to %.3g)"):format(k, d, longest) end
    end
  end
  return nil
end

-- The foot of x on a primitive piece's model (its line, its circle) and the unit tangent
-- there along the traversal.
local function foot(p, x)
  if p.kind == "line" then
    local t = p.t_start
    local u = (x[1] - p.start[1]) * t[1] + (x[2] - p.start[2]) * t[2]
    return { p.start[1] + u * t[1], p.start[2] + u * t[2] }, { t[1], t[2] }
  end
  local c, r, s = p.centre, p.radius, p.sweep > 0 and 1 or -1
  local dx, dy = x[1] - c[1], x[2] - c[2]
  local d = math.sqrt(dx * dx + dy * dy)
  if d == 0 then return nil end
  return { c[1] + r * dx / d, c[2] + r * dy / d }, { -s * dy / d, s * dx / d }
end

-- The point s along a primitive piece's model from x (on it), and the unit tangent there.
local function along(p, x, s)
  if p.kind == "line" then
    local t = p.t_start
    return { x[1] + s * t[1], x[2] + s * t[2] }, { t[1], t[2] }
  end
  local c, r = p.centre, p.radius
  local a = math.atan(x[2] - c[2], x[1] - c[1]) + (p.sweep > 0 and 1 or -1) * s / r
  return foot(p, { c[1] + r * math.cos(a), c[2] + r * math.sin(a) })
end

-- The ends of the bend that softens the corner between A and B: the feet of A's last and
-- B's first samples (a_last, b_first) on their models. Where the samples are closer than
-- the noise, a foot can lie past the corner (A's last a few sigma beyond it, B's first
-- before it) and the bend went back on itself, a small loop; such a foot is moved to the
-- corner's other side, as far from it as it was (at least half the two samples' distance,
-- at most half its piece). Returns the start, its tangent, the end, its tangent (nil when
-- a foot is not defined).
local function bend_ends(A, B, a_last, b_first)
  local ea, ta = foot(A, a_last)
  local sb, tb = foot(B, b_first)
  if not ea or not sb then return nil end
  local x = B.start
  if dist(A["end"], x) > 1e-9 * (dist(ea, x) + dist(sb, x)) then return ea, ta, sb, tb end
  local before = (x[1] - ea[1]) * ta[1] + (x[2] - ea[2]) * ta[2]
  local after = (sb[1] - x[1]) * tb[1] + (sb[2] - x[2]) * tb[2]
  local least = 0.5 * dist(a_last, b_first)
  if not (before > 0) then
    ea, ta = along(A, x, -math.min(math.max(-before, least), 0.5 * dist(A.start, x)))
  end
  if not (after > 0) then
    sb, tb = along(B, x, math.min(math.max(-after, least), 0.5 * dist(x, B["end"])))
  end
  if not ea or not sb then return nil end
  return ea, ta, sb, tb
end

-- Softens the corner where pieces[i] starts into a smooth bend: the samples next to it (the
-- last of the piece before, the first of pieces[i]; the shared one when the corner is
-- sampled) become a free run joined tangentially to both, fitted like any free run. For a
-- corner the data do not confirm (its evidence in sigma^2 below what noise gives): the
-- samples cannot tell it from a bend one or two steps wide, and the bend keeps the rest of
-- the section's lines and arcs. Returns the new list, or nil when a side is too short.
function M.soften(P, pieces, i)
  local n, m = #pieces, #P
  local ia = (i - 2) % n + 1
  local A, B = pieces[ia], pieces[i]
  if A.kind == "free" or B.kind == "free" or ia == i then return nil end
  local shared = (A.first - 1 + A.count - 1) % m + 1 == B.first
  local giveA, giveB = shared and 0 or 1, 1
  -- sides of 3 samples or fewer are what a fillet sampled as a polygon leaves: no bend
  -- between those, the section keeps the smooth path
  if A.count < 4 or B.count < 4 then return nil end
  local F = { kind = "free", first = shared and B.first or (A.first - 1 + A.count - 1) % m + 1,
              count = shared and 1 or 2, join = "tangent" }
  local a_last = { P:get((A.first - 1 + A.count - 1 - giveA) % m + 1) }
  local b_first = { P:get((B.first - 1 + giveB) % m + 1) }
  local ea, ta, sb, tb = bend_ends(A, B, a_last, b_first)
  if not ea then return nil end
  local A2, B2 = {}, {}
  for k, v in pairs(A) do A2[k] = v end
  for k, v in pairs(B) do B2[k] = v end
  A2.count = A.count - giveA
  B2.first, B2.count, B2.join = (B.first - 1 + giveB) % m + 1, B.count - giveB, "tangent"
  B2.turn, B2.evidence = nil, nil
  if A.kind == "arc" then A2.sweep = A.sweep + angle(A.centre, A["end"], ea) end
  if B.kind == "arc" then B2.sweep = B.sweep - angle(B.centre, B.start, sb) end
  A2["end"], A2.t_end = ea, ta
  B2.start, B2.t_start = sb, tb
  F.start, F.t_start, F["end"], F.t_end = ea, ta, sb, tb
  local out = {}
  for k, p in ipairs(pieces) do
    if k == ia then out[#out + 1] = A2
    elseif k == i then out[#out + 1] = F; out[#out + 1] = B2
    else out[#out + 1] = p end
  end
  return out
end

-- 1-based samples nearest to the corners (for rep.corners)
function M.corner_samples(P, pieces)
  local out, m = {}, #P
  for _, p in ipairs(pieces) do
    if p.join == "corner" then
      local best, bi = math.huge, 1
      for _, i in ipairs { p.first, (p.first - 2) % m + 1 } do
        local d = dist({ P:get(i) }, p.start)
        if d < best then best, bi = d, i end
      end
      out[#out + 1] = bi
    end
  end
  table.sort(out)
  return out
end

-- Pieces found on a subset of the samples (the trusted ones: a gross outlier of weight
-- 1e-3 is no sample of a line), given back on all m samples: idx[j] is the index among
-- all of the subset's j-th sample. Each piece keeps its samples and takes the left-out
-- ones after them, up to the next piece's first (open: the first piece also those before
-- it); a piece of no samples (a bridge) starts at the next piece's first. The models,
-- ends and residuals (rms, max: of the subset's samples) stay.
function M.spread(pieces, idx, m, closed)
  local out, n = {}, #pieces
  for k, p in ipairs(pieces) do
    local q = {}
    for key, v in pairs(p) do q[key] = v end
    q.first = idx[p.first]
    out[k] = q
  end
  local function next_first(k) -- the first sample of the next piece holding any
    for s = 1, n do
      local q = out[(k - 1 + s) % n + 1]
      if q.count > 0 and ((k - 1 + s) < n or closed) then return q.first end
    end
    return m + 1 -- open: the last piece runs to the end
  end
  for k, q in ipairs(out) do
    if q.count > 0 then
      if k == 1 and not closed then q.first = 1 end
      q.count = (next_first(k) - 1 - q.first) % m + 1 -- all m: a closed section's only one
    else
      local f = next_first(k)
      q.first = f <= m and f or m
    end
    q.last = (q.first - 1 + math.max(q.count - 1, 0)) % m + 1
  end
  return out
end

return M
