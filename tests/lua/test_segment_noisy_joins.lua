-- test_segment_noisy_joins.lua: where the pieces of a noisy section meet (bs.geom.segment).
-- Generated outlines of lines and arcs (shapes_sharp: rounded rectangles, filleted
-- polygons, slots, keyholes, D shapes), sampled densely (20 to 250 samples per side) with
-- noise of 1e-4 to 3e-3 of the size, many seeds:
--   - a line meets the arc it touches (a fillet, a slot's end) at their touching point,
--     however densely the arc is sampled: no bridge (a free piece of no samples) between
--     them. The line runs within the tolerance of the arc for sqrt(2 r tol) past that
--     point, and the join used to be looked for only within a few of the arc's own sample
--     spacings: 113 of 240 sections had a bridge;
--   - a D's arc keeps its last samples: no short line of them between the arc and the
--     corner, which moved the corner out by a third of the noise.
local T = require "tap"
local bs = require "bsfit"
local shapes = require "shapes_sharp"

local ALL = shapes.all()

local function bridges(pieces)
  local n = 0
  for _, p in ipairs(pieces) do
    if p.kind == "free" and p.count == 0 then n = n + 1 end
  end
  return n
end

-- the joins of a line and an arc along o (all tangent on the shapes where they are counted)
local function line_arc_joins(o)
  local n = 0
  for i, q in ipairs(o.prims) do
    if q.kind ~= o.prims[(i - 2) % #o.prims + 1].kind then n = n + 1 end
  end
  return n
end
local ALL_TANGENT = { rrect = true, hexagon = true, pentagon = true, slot = true }

T.test("a line meets the arc it touches however densely the arc is sampled", function()
  local total, with_bridge, found, truth = 0, {}, 0, 0
  for _, name in ipairs { "rrect", "hexagon", "pentagon", "slot", "keyhole", "D" } do
    local o = ALL[name]
    local size = shapes.size(o)
    for _, per in ipairs { 30, 60, 120, 250 } do
      for _, rel in ipairs { 1e-4, 3e-4 } do
        for seed = 1, 5 do
          local sigma = rel * size
          local pts = shapes.sample(o, per, { sigma = sigma, seed = 31 * seed + per })
          local pieces = bs.geom.segment(bs.points.new(pts), { closed = true, sigma = sigma })
          total = total + 1
          if bridges(pieces) > 0 then
            with_bridge[#with_bridge + 1] = ("%s %d per side noise %g seed %d"):format(name, per, rel, seed)
          end
          if ALL_TANGENT[name] then
            truth = truth + line_arc_joins(o)
            for i, p in ipairs(pieces) do
              local q = pieces[(i - 2) % #pieces + 1]
              if p.join == "tangent" and p.kind ~= q.kind and p.kind ~= "free" and q.kind ~= "free" then
                found = found + 1
              end
            end
          end
        end
      end
    end
  end
  print(("# %d of %d sections with a bridge: %s"):format(#with_bridge, total, table.concat(with_bridge, ", ")))
  -- 113 before; the 18 left are mostly one side split in two lines that continue each
  -- other (which bsfit.strategy.noisy_pieces accepts)
  T.ok(#with_bridge <= 0.1 * total, ("%d of %d sections with a bridge"):format(#with_bridge, total))
  print(("# %d of %d tangent joins of a line and an arc found"):format(found, truth))
  T.ok(found >= 0.9 * truth and found <= truth, ("%d of %d tangent joins found"):format(found, truth))
end)

T.test("a noisy D's arc keeps its last samples: two pieces, corners within 3 sigma", function()
  local o = ALL.D
  local size = shapes.size(o)
  local total, wrong = 0, {}
  for _, per in ipairs { 20, 40, 75 } do
    for _, rel in ipairs { 1e-3, 3e-3 } do
      for seed = 1, 8 do
        local sigma = rel * size
        local pts = shapes.sample(o, per, { sigma = sigma, seed = 7 * seed + per, uneven = seed % 2 == 0 })
        local P = bs.points.new(pts)
        local w = bs.geom.noise_sigma(P, { closed = true })
        local s = bs.geom.segment_sigma(P, { closed = true, max = 1.25 * w })
        local pieces = bs.geom.segment(P, { closed = true, sigma = s > 0 and s or w })
        total = total + 1
        local what = ("D %d per side noise %g seed %d"):format(per, rel, seed)
        local ok = #pieces == 2
        for _, p in ipairs(pieces) do
          local near = math.huge
          for _, c in ipairs(o.corners) do near = math.min(near, shapes.dist(p.start, c)) end
          ok = ok and near <= 3 * sigma
        end
        if not ok then wrong[#wrong + 1] = ("%s: %d pieces"):format(what, #pieces) end
      end
    end
  end
  print(("# %d of %d D shapes not two pieces with their corners: %s"):format(#wrong, total, table.concat(wrong, ", ")))
  T.ok(#wrong <= 0.05 * total, ("%d of %d D shapes not two pieces with their corners"):format(#wrong, total))
end)

T.run()
