-- test_segment_weighed.lua: bs.geom.segment's param_cost (on noisy data a piece costs its
-- residual in sigma^2 and param_cost sigma^2 per parameter; math.huge: parameters only).
-- What the weighing gains is measured by the sweep of test_sharp_noisy.lua (its floor of
-- sections within the Hausdorff bound fails with parameters only: 193 instead of 203).
local T = require "tap"
local bs = require "bsfit"

T.test("param_cost: checked; a square's four sides either way", function()
  local P = bs.points.new { { 0, 0 }, { 1, 0 }, { 2, 0 }, { 2, 1 }, { 2, 2 }, { 1, 2 }, { 0, 2 }, { 0, 1 } }
  local want = { match = "field 'param_cost' must be > 0" }
  T.raises(want, function() bs.geom.segment(P, { sigma = 0.01, param_cost = 0 }) end)
  T.raises(want, function() bs.geom.segment(P, { sigma = 0.01, param_cost = -1 }) end)
  T.raises({ match = "param_cost" }, function() bs.geom.segment(P, { sigma = 0.01, param_cost = "x" }) end)
  T.eq(#bs.geom.segment(P, { sigma = 0.01, param_cost = math.huge }), 4)
  T.eq(#bs.geom.segment(P, { sigma = 0.01 }), 4)
end)
