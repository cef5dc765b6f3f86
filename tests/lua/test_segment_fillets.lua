-- test_segment_fillets.lua: a noisy fillet of few samples is read as the arc tangent to the
-- lines either side (segment_fillets.c: a short line between two corners, or an arc that
-- misses the tangency, becomes that fillet), and a short side between two right angles
-- is not. Random convex polygons of 3 to 7 vertices, each vertex filleted or not at
-- random, lines of 5 to 8 samples, fillets of 4 to 6, noise 1e-4 to 1e-3 of the size,
-- even and uneven, segmented at their true noise.
local T = require "tap"
local bs = require "bsfit"
local shapes = require "shapes_sharp"

-- a random convex polygon of 3 to 7 vertices, 8 to 12 from its centre, 60% of them filleted
local function random_outline(uniform)
  return shapes.random_filleted(uniform, 3 + math.floor(5 * uniform()),
    function() return 10 * (0.8 + 0.4 * uniform()) end,
    function(room) return uniform() < 0.6 and room * (0.4 + 0.6 * uniform()) or 0 end)
end

-- How well n evenly spread samples fix the radius of fillet q with its lines known: the
-- standard error of the radius, relative to it, at noise sigma. The fillet's centre lies
-- on the bisector of its corner, k r from it (k = 1 / cos(turn / 2)): a sample at angle phi
-- from the bisector moves by k cos(phi) - 1 per unit of radius.
local function radius_se(q, n, sigma)
  local turn, info = math.abs(q.sweep), 0
  local k = 1 / math.cos(turn / 2)
  for j = 1, n do
    local phi = ((j - 0.5) / n - 0.5) * turn
    info = info + (k * math.cos(phi) - 1) ^ 2
  end
  return sigma / math.sqrt(info) / q.r
end

-- the piece of `pieces` that reads true arc q: an arc centred near q's centre, tangent to
-- its neighbours at both ends; nil when none
local function fillet_of(pieces, q)
  for i, p in ipairs(pieces) do
    local nxt = pieces[i % #pieces + 1]
    if p.kind == "arc" and shapes.dist(p.centre, q.c) < 0.5 * q.r and p.join == "tangent" and
       nxt.join == "tangent" then return p end
  end
  return nil
end

-- Fillets whose samples fix their radius to half a percent (406 of them): 87% came out as
-- tangent arcs and 80% within 2% of their radius before (the rest as a short line between
-- two corners, or as an arc meeting a line at a corner of a few degrees), 96% and 90% now.
T.test("noisy fillets of 4 to 6 samples are arcs tangent to their lines, radii within 2%", function()
  local uniform = shapes.rng(4242)
  local fillets, tangent, exact = 0, 0, 0
  for case = 1, 400 do
    local o = random_outline(uniform)
    local sigma = 10 ^ (-4 + uniform()) * shapes.size(o)
    local per_line, per_arc = 5 + math.floor(4 * uniform()), 4 + math.floor(3 * uniform())
    local pts = shapes.sample(o, function(q) return q.kind == "arc" and per_arc or per_line end,
                              { sigma = sigma, seed = 1000 + case, uneven = uniform() < 0.5 })
    local pieces = bs.geom.segment(bs.points.new(pts), { closed = true, sigma = sigma })
    for _, q in ipairs(o.prims) do
      if q.kind == "arc" and radius_se(q, per_arc, sigma) < 0.005 then
        local p = fillet_of(pieces, q)
        fillets = fillets + 1
        if p then tangent = tangent + 1 end
        if p and math.abs(p.radius - q.r) <= 0.02 * q.r then exact = exact + 1 end
      end
    end
  end
  print(("# %d fillets: %d tangent arcs, %d of them within 2%% of the radius"):format(fillets, tangent, exact))
  T.ok(fillets >= 300, "enough fillets")
  T.ok(tangent >= 0.93 * fillets, ("%d of %d fillets tangent arcs"):format(tangent, fillets))
  T.ok(exact >= 0.85 * fillets, ("%d of %d fillets within 2%% of their radius"):format(exact, fillets))
end)

-- The end of a bar (a letter's stem) is a short side between two right angles: four samples
-- across a stem 50 sigma wide fit a semicircle within 20 sigma^2, so a fillet paid for at
-- the cover's price of a parameter (32 sigma^2) took it.
T.test("a bar's square end is two corners, not a semicircle", function()
  local uniform = shapes.rng(77)
  for case = 1, 60 do
    local w, l = 1, 4 + 6 * uniform()
    local o = shapes.filleted({ { 0, 0 }, { l, 0 }, { l, w }, { 0, w } })
    local sigma = (1 + 2 * uniform()) * 1e-3 * shapes.size(o)
    local per = 4 + math.floor(3 * uniform())
    local pts = shapes.sample(o, per, { sigma = sigma, seed = 500 + case, uneven = uniform() < 0.5 })
    for _, p in ipairs(bs.geom.segment(bs.points.new(pts), { closed = true, sigma = sigma })) do
      -- (a long side may come out as an arc of a radius of hundreds, within the noise)
      T.ok(p.kind ~= "arc" or p.radius > 2 * w, ("bar %d (%.2f x 1, %d per side, noise %.3g): an arc of radius %.3g"):format(
        case, l, per, sigma, p.radius or 0))
    end
  end
end)
