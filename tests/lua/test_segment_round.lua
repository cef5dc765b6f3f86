-- test_segment_round.lua: when the samples of a closed section all lie on one circle, its
-- one arc goes round the whole circle exactly when the closing step (last sample to first)
-- turns no more than 1.5 times the longest of the other steps; otherwise it is an open arc.
-- Exact samples at angles built step by step (so the steps' turns are known): uneven
-- steps, the longest anywhere along the section (among 4 .. 2000 samples, turning up to
-- 1.3 pi, so that every half plane holds a longest step), both directions, any centre,
-- radius and start, closing steps from 0.6 to 2.4 times the longest (none within 3% of
-- the bound).
local T = require "tap"
local bs = require "bsfit"

local seed = 7
local function rnd()
  seed = (seed * 1103515245 + 12345) % 2147483648
  return (seed + 0.5) / 2147483648
end

-- the turns of the m - 1 steps and the closing one: the longest at step at, the others
-- uneven, 0.2 .. 0.8 of it, scaled so that the closing turn is ratio times the longest
local function turns(m, at, ratio)
  local t, sum = {}, 0
  for k = 1, m - 1 do
    t[k] = k == at and 1 or 0.2 + 0.6 * rnd()
    sum = sum + t[k]
  end
  local scale = 2 * math.pi / (sum + ratio) -- the longest's turn
  for k = 1, m - 1 do t[k] = t[k] * scale end
  return t, ratio * scale
end

T.test("a closed section's one arc is whole exactly when its closing step is short", function()
  local cases = 0
  for _, m in ipairs { 24, 40, 100, 300, 2000 } do
    for _, ratio in ipairs { 0.6, 1.2, 1.45, 1.55, 1.8, 2.4 } do
      for _ = 1, 6 do
        local at = 1 + math.floor(rnd() * (m - 1))
        local t, closing = turns(m, at, ratio)
        local longest = t[at]
        local r, cx, cy = 10 ^ (4 * rnd() - 2), 100 * rnd() - 50, 100 * rnd() - 50
        local a, dir, pts = 2 * math.pi * rnd(), rnd() < 0.5 and 1 or -1, {}
        for k = 1, m do
          pts[k] = { cx + r * math.cos(a), cy + r * math.sin(a) }
          if k < m then a = a + dir * t[k] end
        end
        local pieces = assert(bs.geom.segment(bs.points.new(pts), { closed = true }))
        local what = string.format("m %d, longest %.3g rad at step %d, closing %.3g (%.2f x)",
                                   m, longest, at, closing, ratio)
        -- whole: one arc round the circle; else an arc of the samples' turn (and the chord)
        local arc = pieces[1]
        T.eq(arc.kind, "arc", what)
        local whole = #pieces == 1 and math.abs(math.abs(arc.sweep) - 2 * math.pi) < 1e-9
        T.eq(whole, closing <= 1.5 * longest, what .. ": whole circle")
        if not whole then
          T.near(math.abs(arc.sweep), 2 * math.pi - closing, 1e-9, what .. ": sweep")
        end
        cases = cases + 1
      end
    end
  end
  T.ok(cases == 5 * 6 * 6, "cases " .. cases)
end)
