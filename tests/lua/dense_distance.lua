-- dense_distance.lua: an independent measure of the distance from a point to a curve, for
-- the closest-point tests (no Newton, no sample bracket): the curve evaluated at 400 points
-- per knot span, then around every local minimum of those (not only the nearest: a narrow
-- valley's bottom can lie nearer than the nearest sample) 20 evaluations, 14 times, each
-- round a tenth as wide. Every value is a point of the curve, so the result is an upper
-- bound of the true distance, and close to it.
--   local dense = require "dense_distance"
--   dense.distance(C, x, y, dense.distinct(knots))
local M = {}

-- |C(t) - (x, y)|^2
function M.dist2(C, t, x, y)
  local px, py = C:eval(t)
  return (px - x) ^ 2 + (py - y) ^ 2
end

local function zoom(C, x, y, a, b, lo, hi)
  local best, n = math.huge, 20
  for _ = 1, 14 do
    local bt, bd = lo, math.huge
    for j = 0, n do
      local t = lo + (hi - lo) * j / n
      local dd = M.dist2(C, t, x, y)
      if dd < bd then bd, bt = dd, t end
    end
    best = math.min(best, bd)
    local h = (hi - lo) / n
    lo, hi = math.max(a, bt - h), math.min(b, bt + h)
  end
  return best
end

-- the distance from (x, y) to C over its distinct knots kn (sorted)
function M.distance(C, x, y, kn)
  local best, n = math.huge, 400
  for s = 1, #kn - 1 do
    local a, b = kn[s], kn[s + 1]
    if b > a then
      local d, h = {}, (b - a) / n
      for j = 0, n do d[j] = M.dist2(C, a + h * j, x, y) end
      for j = 0, n do
        if (j == 0 or d[j] <= d[j - 1]) and (j == n or d[j] <= d[j + 1]) then
          best = math.min(best, d[j], zoom(C, x, y, a, b, math.max(a, a + (j - 1) * h),
                                           math.min(b, a + (j + 1) * h)))
        end
      end
    end
  end
  return math.sqrt(best)
end

-- the distinct values of a sorted knot vector
function M.distinct(K)
  local kn = {}
  for _, v in ipairs(K) do
    if kn[#kn] ~= v then kn[#kn + 1] = v end
  end
  return kn
end

return M
