-- test_segment_weighed.lua: bs.geom.segment's param_cost (on noisy data a piece costs its
-- residual in sigma^2 and param_cost sigma^2 per parameter; math.huge: parameters only).
-- What the weighing gains on the auto strategy is measured by the sweep of
-- test_sharp_noisy.lua (its floor fails with parameters only: 193 instead of 203 sections
-- within the Hausdorff bound); here, what it does to the cover itself, and how many
-- distinct samples a run of a noisy cover holds (runs denser than the noise, repeats).
local T = require "tap"
local bs = require "bsfit"
local shapes = require "shapes_sharp"

T.test("param_cost: checked; a square's four sides either way", function()
  local P = bs.points.new { { 0, 0 }, { 1, 0 }, { 2, 0 }, { 2, 1 }, { 2, 2 }, { 1, 2 }, { 0, 2 }, { 0, 1 } }
  local want = { match = "field 'param_cost' must be > 0" }
  T.raises(want, function() bs.geom.segment(P, { sigma = 0.01, param_cost = 0 }) end)
  T.raises(want, function() bs.geom.segment(P, { sigma = 0.01, param_cost = -1 }) end)
  T.raises({ match = "param_cost" }, function() bs.geom.segment(P, { sigma = 0.01, param_cost = "x" }) end)
  T.eq(#bs.geom.segment(P, { sigma = 0.01, param_cost = math.huge }), 4)
  T.eq(#bs.geom.segment(P, { sigma = 0.01 }), 4)
end)

-- the kinds of a cover's pieces (a sorted signature) and its lines' and arcs' residual
local function cover_of(pieces)
  local kinds, rss = {}, 0
  for _, p in ipairs(pieces) do
    kinds[#kinds + 1] = p.kind
    if p.kind ~= "free" then rss = rss + p.rms ^ 2 * p.count end
  end
  table.sort(kinds)
  return table.concat(kinds, " "), rss
end

-- Among covers of as many parameters the weighed one explains the samples best: where
-- both covers hold the same pieces, its residual is lower far more often than higher
-- (higher only where the boundaries settle differently afterwards). 156 sections of
-- every outline, 4 to 10 samples per side, noise 1e-3 and 3e-3, even and uneven, at the
-- true noise. With the weighing off both counts are 0.
T.test("weighed, covers of the same pieces explain their samples better", function()
  local ALL, lower, higher = shapes.all(), 0, 0
  for k, name in ipairs(shapes.names()) do
    local size = shapes.size(ALL[name])
    for _, per in ipairs { 4, 6, 10 } do
      for j, rel in ipairs { 1e-3, 3e-3 } do
        for _, uneven in ipairs { false, true } do
          local P = bs.points.new(shapes.sample(ALL[name], per, { sigma = rel * size,
                                                seed = 31 * k + 7 * per + j, uneven = uneven }))
          local ka, ra = cover_of(bs.geom.segment(P, { sigma = rel * size }))
          local kb, rb = cover_of(bs.geom.segment(P, { sigma = rel * size, param_cost = math.huge }))
          if ka == kb and ra < rb * (1 - 1e-9) then lower = lower + 1 end
          if ka == kb and ra > rb * (1 + 1e-9) then higher = higher + 1 end
        end
      end
    end
  end
  print(("# same pieces, weighed residual lower on %d sections, higher on %d"):format(lower, higher))
  T.ok(lower >= 30 and higher * 5 <= lower, "the weighed cover's residual is the lower one")
end)

-- A short side sampled more densely than the noise (every step shorter than the tolerance,
-- 4 sigma) is still a line: it counts the tolerances it spans end to end. Before, such a
-- run counted as one distinct sample and held no line: the short sides of these
-- rectangles (a serif's sides) came out free runs and their corners were lost. In 8 of
-- these 12 the short side's step is below the tolerance; the other 4 are ordinary sides.
T.test("short sides sampled more densely than the noise are lines", function()
  local _, gauss = require("synth").rng(4242)
  for _, short in ipairs { 0.12, 0.2, 0.3 } do
    for _, per in ipairs { 30, 60 } do
      for _, rel in ipairs { 1e-3, 3e-3 } do
        local corners = { { 0, 0 }, { 1, 0 }, { 1, short }, { 0, short } }
        local pts = {}
        for k = 1, 4 do
          local a, b = corners[k], corners[k % 4 + 1]
          for i = 0, per - 1 do
            local t = (i + 0.5) / per
            pts[#pts + 1] = { a[1] + t * (b[1] - a[1]) + rel * gauss(),
                              a[2] + t * (b[2] - a[2]) + rel * gauss() }
          end
        end
        local pieces = bs.geom.segment(bs.points.new(pts), { closed = true, sigma = rel })
        local what = ("short side %g, %d per side, noise %g"):format(short, per, rel)
        local lines, corners_found = 0, 0
        for _, p in ipairs(pieces) do
          if p.kind == "line" then lines = lines + 1 end
          if p.join == "corner" then corners_found = corners_found + 1 end
        end
        T.eq(#pieces, 4, what .. ": pieces")
        T.eq(lines, 4, what .. ": lines")
        T.eq(corners_found, 4, what .. ": corners")
      end
    end
  end
end)

-- Samples given several times are one sample each: a noisy circle's samples repeated
-- three times hold no line of two positions (six samples spanning many tolerances: counted
-- by their span alone they made such lines; and where a line of three positions gave its
-- last samples to its neighbour, it kept two). Exact data never count by span
-- (test_strategy: a circle's samples three times each).
T.test("repeated noisy samples hold no line of two positions", function()
  local _, gauss = require("synth").rng(77)
  for _, k in ipairs { 12, 20, 30, 40, 60 } do
    for _, rel in ipairs { 1e-4, 3e-4, 1e-3 } do
      local rows = {}
      for i = 0, k - 1 do
        local a = 2 * math.pi * i / k
        local x, y = math.cos(a) + rel * gauss(), math.sin(a) + rel * gauss()
        for _ = 1, 3 do rows[#rows + 1] = { x, y } end
      end
      local pieces = bs.geom.segment(bs.points.new(rows), { closed = true, sigma = rel })
      for i, p in ipairs(pieces) do
        if p.kind == "line" then
          local positions = 0 -- its samples that differ from the one before
          for j = 1, p.count - 1 do
            local a, b = rows[(p.first + j - 2) % #rows + 1], rows[(p.first + j - 1) % #rows + 1]
            if a[1] ~= b[1] or a[2] ~= b[2] then positions = positions + 1 end
          end
          local what = ("circle of %d samples x 3, noise %g: line %d"):format(k, rel, i)
          T.ok(positions + 1 >= 3, ("%s of %d samples holds %d positions"):format(what, p.count,
                                                                                positions + 1))
        end
      end
    end
  end
end)
