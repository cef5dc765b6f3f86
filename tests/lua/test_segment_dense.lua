-- test_segment_dense.lua: densely sampled exact sections of lines and arcs (issue 14's
-- promise for clean data, 10^3 .. 10^5 samples): bs.geom.segment finds the true pieces
-- (kinds, radii and centres to 1e-9, corners to 1e-9 of the size) and the auto strategy's
-- one curve lies within 1e-9 of the size of the true outline everywhere, measured against
-- the outline itself (tests/lua/shapes_sharp.lua), not at the samples only. Outlines are
-- scaled to sizes 1e-2 .. 1e3 and moved far from the origin. Before the circle fit took its
-- steps in the arc's own frame, 4 samples of a dense arc (2e-3 rad at 10^4 samples of a
-- circle) were refused by its normal equations: a circle of 10^4 samples came out free,
-- and a D of 10^5 samples 3.8e-4 of its size off.
local T = require "tap"
local bs = require "bsfit"
local shapes = require "shapes_sharp"
local auto = require "bsfit.strategy.auto"

local dist = shapes.dist

-- {======================================================================
-- Outlines, moved and scaled
-- =======================================================================

-- outline o scaled by k about the origin, then moved by (dx, dy)
local function placed(o, k, dx, dy)
  local function pt(p) return { k * p[1] + dx, k * p[2] + dy } end
  local out = { prims = {}, corners = {} }
  for _, q in ipairs(o.prims) do
    if q.kind == "line" then
      out.prims[#out.prims + 1] = { kind = "line", a = pt(q.a), b = pt(q.b) }
    else
      out.prims[#out.prims + 1] = { kind = "arc", c = pt(q.c), r = k * q.r, a0 = q.a0,
                                    sweep = q.sweep }
    end
  end
  for _, v in ipairs(o.corners) do out.corners[#out.corners + 1] = pt(v) end
  return out
end

-- a full circle of radius r about c, as four quarters (so that uneven samples, which keep
-- off the ends of each primitive, leave no gap): one arc, no corner
local function circle(c, r)
  local prims = {}
  for k = 0, 3 do
    prims[#prims + 1] = { kind = "arc", c = c, r = r, a0 = 0.3 + k * math.pi / 2,
                          sweep = math.pi / 2 }
  end
  return { prims = prims, corners = {} }
end

-- how many lines and arcs the outline has, consecutive arcs of one circle counted once
local function kinds(o)
  local want, n = { line = 0, arc = 0 }, #o.prims
  for i, q in ipairs(o.prims) do
    local p = o.prims[(i - 2) % n + 1]
    local same = n > 1 and q.kind == "arc" and p.kind == "arc" and p.r == q.r
                 and dist(p.c, q.c) == 0
    if not same then want[q.kind] = want[q.kind] + 1 end
  end
  if want.line == 0 and want.arc == 0 then want.arc = 1 end
  return want
end

-- about m samples of o, spread over its primitives by length (at least 8 on each)
local function sampled(o, m, uneven, seed)
  local total = 0
  for _, q in ipairs(o.prims) do total = total + shapes.length(q) end
  local function per(q) return math.max(8, math.floor(m * shapes.length(q) / total + 0.5)) end
  return shapes.sample(o, per, { uneven = uneven, seed = seed })
end

-- }======================================================================

-- {======================================================================
-- Checks
-- =======================================================================

-- the pieces of bs.geom.segment: as many lines and arcs as the outline has (a tangent
-- join may leave an empty free bridge, which holds no sample), every arc on a true circle
-- (centre and radius to 1e-9), every line's ends on the outline, a corner join at each
-- true corner and nowhere else
local function check_segment(P, o, size, what, lim)
  lim = lim or 1e-9 * size
  local pieces = bs.geom.segment(P, { closed = true })
  local want, got = kinds(o), { line = 0, arc = 0, free = 0 }
  local corners = {}
  for i, p in ipairs(pieces) do
    if p.kind == "free" then
      T.eq(p.count, 0, ("%s: piece %d is free with samples"):format(what, i))
    end
    got[p.kind] = got[p.kind] + 1
    if p.kind == "arc" then
      local tr, off = shapes.true_arc(o, p.centre)
      T.ok(tr and off <= lim and math.abs(p.radius - tr.r) <= math.max(1e-9 * tr.r, lim),
           ("%s: arc %d radius %.17g centre off by %g of the size"):format(what, i, p.radius,
                                                                             off / size))
    elseif p.kind == "line" then
      for _, x in ipairs { p.start, p["end"] } do
        local d = shapes.distance(o, x[1], x[2])
        T.ok(d <= lim, ("%s: line %d ends %g of the size off the outline"):format(what, i,
                                                                                  d / size))
      end
    end
    if p.join == "corner" then corners[#corners + 1] = p.start end
  end
  T.eq(got.line, want.line, what .. ": lines")
  T.eq(got.arc, want.arc, what .. ": arcs")
  T.eq(#corners, #o.corners, what .. ": corners")
  for _, v in ipairs(o.corners) do
    local best = math.huge
    for _, x in ipairs(corners) do best = math.min(best, dist(v, x)) end
    T.ok(best <= lim, ("%s: corner missed by %g of the size"):format(what, best / size))
  end
end

-- auto's curve: through the pieces, within 1e-9 of the size of the true outline both ways
-- (the curve sampled densely against the exact outline, and the outline against the curve)
local function check_auto(P, o, size, what, lim)
  lim = lim or 1e-9 * size
  local C, rep = auto.run(P)
  T.ok(rep.pieces ~= nil, what .. ": auto took the pieces")
  local h = shapes.hausdorff(bs, C, o, 6000, 200)
  T.ok(h <= lim, ("%s: auto's curve %g of the size from the outline"):format(what, h / size))
  T.ok(rep.max <= lim, ("%s: rep.max %g of the size"):format(what, rep.max / size))
end

-- }======================================================================

local SHAPES = {
  D = shapes.d_shape(10), slot = shapes.slot(6, 2), keyhole = shapes.keyhole(3, 1.2, 4),
  rrect = shapes.rounded_rect(60, 30, 1.5), circle = circle({ 0, 0 }, 5),
}
local NAMES = { "D", "slot", "keyhole", "rrect", "circle" }

-- where each outline goes: {scale, dx, dy}, so that its size is 1e-2 .. 1e3 and it lies
-- at the origin or far from it (centre near (1e3, -2e3))
local PLACES = {
  { 1, 0, 0 }, { 1, 1e3, -2e3 }, { 1e-3, 1e3, -2e3 }, { 30, -1e3, 2e3 }, { 1e-2, 0, 0 },
}

-- the size a placement gives an outline: 1e-2 .. 1e3
local function place(name, k)
  local o = SHAPES[name]
  local pl = PLACES[k]
  local scale = pl[1] * 10 / shapes.size(o) -- outlines of size 10 first
  if k == 3 then scale = 1e-2 / shapes.size(o) end
  if k == 4 then scale = 1e3 / shapes.size(o) end
  return placed(o, scale, pl[2], pl[3])
end

T.test("bs.geom.segment on dense exact sections: the true lines, arcs (radii to 1e-9) and corners", function()
  for ni, name in ipairs(NAMES) do
    for _, m in ipairs { 1000, 10000, 30000 } do
      for k = 1, #PLACES do
        for _, uneven in ipairs { false, true } do
          local o = place(name, k)
          local size = shapes.size(o)
          local seed = 100 * ni + k + (uneven and 7 or 0)
          local P = bs.points.new(sampled(o, m, uneven, seed))
          local what = ("%s, %d samples%s, size %.3g at (%g, %g)"):format(name, #P,
            uneven and " uneven" or "", size, PLACES[k][2], PLACES[k][3])
          check_segment(P, o, size, what)
        end
      end
    end
  end
end)

T.test("auto on dense exact sections: the curve within 1e-9 of the size of the true outline everywhere", function()
  for ni, name in ipairs(NAMES) do
    for _, m in ipairs { 1000, 10000, 30000 } do
      for _, k in ipairs { 2, 3, 4 } do
        local uneven = (ni + k + m) % 2 == 1
        local o = place(name, k)
        local P = bs.points.new(sampled(o, m, uneven, 10 * ni + k))
        local what = ("%s, %d samples%s, size %.3g"):format(name, #P, uneven and " uneven" or "",
                                                             shapes.size(o))
        check_auto(P, o, shapes.size(o), what)
      end
    end
  end
end)

T.test("10^5 exact samples of a D shape far from the origin: exact pieces and curve", function()
  local o = place("D", 2)
  local P = bs.points.new(sampled(o, 100000, true, 5))
  check_segment(P, o, shapes.size(o), "D of 10^5 samples")
  check_auto(P, o, shapes.size(o), "D of 10^5 samples")
end)

-- Sections 10^6 and 3 10^6 times their size away from the origin: their coordinates are
-- rounded to 1.1e-16 of their magnitude, 1e-10 of the size and more, so the exact
-- tolerance (1e-10 of the size) has a floor of some 8 units of the coordinates' last
-- place; with it the pieces are still exact to what the coordinates hold (without it a D
-- of size 1e-2 at (1e4, -1e4) had its arc cut into arcs and free runs, 1.3e-9 of its size
-- off, and at (1e5, -1e5) auto raised: its pieces met 1 unit of the last place apart, which
-- bs.curve.join refused). Held to 64 units of the coordinates' last place.
T.test("dense exact sections far from the origin: exact to the rounding of their coordinates", function()
  for ni, name in ipairs(NAMES) do
    for _, far in ipairs { 1e4, 3e4 } do
      for _, m in ipairs { 1000, 10000 } do
        local o = placed(SHAPES[name], 1e-2 / shapes.size(SHAPES[name]), far, -far)
        local size = shapes.size(o)
        local P = bs.points.new(sampled(o, m, m > 1000, ni))
        local lim = math.max(1e-9 * size, 64 * 2.220446049250313e-16 * 2 * far)
        local what = ("%s, %d samples, size %.3g at (%g, %g)"):format(name, #P, size, far, -far)
        check_segment(P, o, size, what, lim)
        check_auto(P, o, size, what, lim)
      end
    end
  end
end)

-- bs.curve.join of parts 10^7 times their size from the origin whose ends differ in the
-- last place of their coordinates: joined (it raised, 1e-9 of their size being less than
-- a unit of that place), and parts a true gap apart still refused.
T.test("bs.curve.join far from the origin: ends within the rounding of their coordinates", function()
  local far, eps = 1e5, 2.220446049250313e-16
  for k = 1, 8 do
    local ulp = far * eps * 2 ^ (k % 3) -- 1, 2 and 4 units of the last place of 1e5 or so
    local a, b = { far, -far }, { far + 1e-2, -far }
    local c = { b[1] + ulp, b[2] - ulp }
    local J = bs.curve.join({ bs.curve.line(a, b), bs.curve.line(c, { far + 1e-2, -far + 1e-2 }) },
                            { 1e-2, 1e-2 })
    local x, y = J:eval(1)
    T.near(x, far + 1e-2, 1e-15, "joined: end x")
    T.near(y, -far + 1e-2, 1e-15, "joined: end y")
  end
  T.raises({ match = "starts" }, function()
    bs.curve.join({ bs.curve.line({ far, -far }, { far + 1e-2, -far }),
                    bs.curve.line({ far + 1e-2, -far + 1e-7 }, { far + 1e-2, -far + 1e-2 }) },
                  { 1e-2, 1e-2 })
  end)
end)

-- The deviation report of the pieces' curve (bs.geom.piece_distances) certifies samples on
-- arcs from their own span's circle, as it does on lines, without the global search
-- (10^5 samples of a circle: 459 -> 4 ms). Points moved off the outline in any direction
-- by up to 1e-2 of the size (past the ends of arcs too, where their feet lie on the next
-- piece): their distances to the curve, which lies on the outline to 1e-9, are their exact
-- distances to the outline.
T.test("bs.geom.piece_distances on arcs: the exact distances of points off the outline", function()
  local uniform = shapes.rng(11)
  for ni, name in ipairs(NAMES) do
    for _, k in ipairs { 1, 2, 3 } do
      local o = place(name, k)
      local size = shapes.size(o)
      local total = 0
      for _, q in ipairs(o.prims) do total = total + shapes.length(q) end
      local P, Q = {}, {}
      for _, q in ipairs(o.prims) do
        local n = math.max(8, math.floor(3000 * shapes.length(q) / total))
        for j = 1, n do
          local f = (j - 0.5) / n
          local x = shapes.at(q, f)
          local d, a = uniform() * 1e-2 * size, 2 * math.pi * uniform()
          P[#P + 1] = x
          Q[#Q + 1] = { x[1] + d * math.cos(a), x[2] + d * math.sin(a) }
        end
      end
      local C, rep = auto.run(bs.points.new(P))
      local what = ("%s (%d), size %.3g"):format(name, ni, size)
      T.ok(rep.pieces ~= nil, what .. ": through the pieces")
      local d = bs.geom.piece_distances(C, bs.points.new(Q), rep.pieces, 8)
      local worst = 0
      for i = 1, #Q do
        worst = math.max(worst, math.abs(d:get(i) - shapes.distance(o, Q[i][1], Q[i][2])))
      end
      T.ok(worst <= 1e-9 * size, ("%s: distances off by %g of the size"):format(what, worst / size))
    end
  end
end)

-- Samples all on one circle but not in order along it (the k-th at angle k times a step,
-- winding round many times: cos i, sin i for i = 1 .. 9119 winds 1451 times) fit the circle
-- to rounding. They were one arc of 1.1 radians plus a bridge, 1.7 (the diameter) from the
-- samples, reported as success without a word. An arc turns round at most once: no piece
-- of theirs is an arc, and auto either follows the samples or says that its curve crosses.
T.test("samples on a circle but not in order along it: no arc, no silent miss", function()
  local warned = 0
  for _, c in ipairs { { 9119, 1.0, 1 }, { 500, 2.5, 3 }, { 2000, 2.399963229728653, 0.01 },
                       { 64, math.pi * 0.75, 1e3 }, { 700, 4.0, 0.2 }, { 3000, -1.3, 40 } } do
    local m, step, r = c[1], c[2], c[3]
    local short = math.abs(math.atan(math.sin(step), math.cos(step))) -- each step the short way
    local pts = {}
    for k = 1, m do pts[k] = { 5 * r + r * math.cos(k * step), -2 * r + r * math.sin(k * step) } end
    local P = bs.points.new(pts)
    local what = ("%d samples, %g rad apart, radius %g"):format(m, step, r)
    for _, p in ipairs(bs.geom.segment(P, { closed = true })) do
      T.ok(p.kind ~= "arc" or p.count * short < 2 * math.pi + short,
           ("%s: an arc of %d samples winds round"):format(what, p.count))
    end
    local C, rep = auto.run(P)
    T.ok(C ~= nil, what .. ": a curve")
    T.ok(rep.max <= 1e-9 * 2 * r or #(rep.warnings or {}) > 0,
         ("%s: max %g without a warning"):format(what, rep.max))
    -- and the warning says what is wrong with the samples
    if rep.crossings > 0 then
      T.ok(table.concat(rep.warnings, " "):find("in order along the outline", 1, true) ~= nil,
           what .. ": " .. table.concat(rep.warnings, "; "))
      warned = warned + 1
    end
  end
  -- the warning's wording was checked at all (9119 samples 1 rad apart cross themselves)
  T.ok(warned >= 1, "no case crossed itself")
end)
