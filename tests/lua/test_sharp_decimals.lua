-- test_sharp_decimals.lua: sections written with a few decimals (a CSV of 4 or 6 decimals,
-- as scanners and CAD exports write them). Their samples are exact shapes rounded to half a
-- unit of the last decimal: not exact to 1e-10 of the size, which the segmentation's exact
-- tolerance asked of them, and far below any noise the windows can read. Before, a D of 10
-- samples per side written with 6 decimals had its arc cut into free runs at both ends,
-- which rounded its corners: 2.5% of its size off; a keyhole 0.5%; the demo's bracket had
-- its fillets meet its lines at corners of 0.07 degrees. The segmentation now takes the
-- decimal grid every coordinate lies on as a floor of its exact tolerance (segment.c,
-- decimal_floor: the grid's unit, where it is at most 1e-5 of the size), and
-- the exact path refuses arcs that meet at corners of less than a degree (sharp.lua,
-- slight_corner): smooth curves written so, read as chains of short arcs, keep the
-- smooth path or their tangent arcs, never false corners.
local T = require "tap"
local bs = require "bsfit"
local shapes = require "shapes_sharp"
local synth = require "synth"
local auto = require "bsfit.strategy.auto"

local DEMO = (debug.getinfo(1, "S").source:match("^@(.*)/[^/]*$") or ".") .. "/../data/demo/"

local function rounded(pts, decimals)
  local f, out = 10 ^ decimals, {}
  for i, p in ipairs(pts) do
    out[i] = { math.floor(p[1] * f + 0.5) / f, math.floor(p[2] * f + 0.5) / f }
  end
  return out
end

local function joins(rep)
  local corners, tangents = 0, 0
  for _, p in ipairs(rep.pieces or {}) do
    if p.join == "corner" then corners = corners + 1 elseif p.join == "tangent" then tangents = tangents + 1 end
  end
  return corners, tangents
end

T.test("outlines written with 4 and 6 decimals: exact to their decimals, the true corners", function()
  local n = 0
  for _, decimals in ipairs { 4, 6 } do
    local unit = 10 ^ -decimals
    for _, name in ipairs(shapes.names()) do
      local o = shapes.all()[name]
      for seed = 1, 2 do
        for _, uneven in ipairs { false, true } do
          local pts = rounded(shapes.sample(o, 10, { seed = seed, uneven = uneven }), decimals)
          local C, rep = auto.run(bs.points.new(pts))
          local what = ("%s, 10 %s samples per side, %d decimals (seed %d)"):format(name,
            uneven and "uneven" or "even", decimals, seed)
          local h = shapes.hausdorff(bs, C, o, 4000, 100)
          T.ok(rep.pieces ~= nil, what .. ": pieces")
          T.ok(h <= 10 * unit, ("%s: %.3g from the true outline, the unit %g"):format(what, h, unit))
          T.eq((joins(rep)), #o.corners, what .. ": corners")
          T.eq(rep.crossings, 0, what .. ": crossings")
          n = n + 1
        end
      end
    end
  end
  T.eq(n, 104, "sections")
end)

T.test("smooth shapes written with 5 and 6 decimals: no corner, no loop", function()
  local SMOOTH, names = synth.smooth_shapes()
  local false_corners = {}
  for _, decimals in ipairs { 5, 6 } do
    for _, name in ipairs(names) do
      for _, m in ipairs { 24, 80, 200, 1000 } do
        for _, uneven in ipairs { false, true } do
          local pts = rounded(synth.sample_smooth(SMOOTH[name], m, uneven), decimals)
          local what = ("%s %d points %d decimals%s"):format(name, m, decimals, uneven and " uneven" or "")
          local C, rep = auto.run(bs.points.new(pts))
          synth.check_smooth(T, C, rep, what, false_corners)
        end
      end
    end
  end
  print(("# %d with a corner: %s"):format(#false_corners, table.concat(false_corners, ", ")))
  T.eq(#false_corners, 0, "smooth sections with a corner")
end)

T.test("the demo's bracket (6 decimals): its fillets meet its lines tangentially", function()
  local P = assert(bs.points.read(DEMO .. "bracket.csv"))
  local _, rep = auto.run(P)
  local arcs, tangent_arcs = 0, 0
  for i, p in ipairs(rep.pieces) do
    local q = rep.pieces[i % #rep.pieces + 1]
    if p.kind == "arc" then
      arcs = arcs + 1
      if p.join == "tangent" and q.join == "tangent" then tangent_arcs = tangent_arcs + 1 end
      T.near(p.radius, 3, 1e-6, "fillet radius")
    end
  end
  T.eq(arcs, 4, "fillets")
  T.eq(tangent_arcs, 4, "fillets tangent at both ends")
  T.eq((joins(rep)), 4, "corners: the notch's four")
end)

-- The demo's cam (README's table): a base circle of radius 20 and a lobe, 6 decimals. One
-- smooth curve 1.6e-3 from its samples before; its base circle one exact arc now, the lobe
-- a free run, every sample within the rounding.
T.test("the demo's cam (6 decimals): its base circle one arc of radius 20", function()
  local _, rep = auto.run(assert(bs.points.read(DEMO .. "cam.csv")))
  local arcs = {}
  for _, p in ipairs(rep.pieces or {}) do
    if p.kind == "arc" then arcs[#arcs + 1] = p end
  end
  T.eq(#arcs, 1, "one arc")
  T.near(arcs[1].radius, 20, 1e-6, "its radius")
  T.ok(rep.max <= 1e-6, ("%.3g from a sample"):format(rep.max))
  T.eq((joins(rep)), 0, "no corner")
end)
