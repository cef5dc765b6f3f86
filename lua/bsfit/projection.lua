-- lua/bsfit/projection.lua
-- The best-fit plane of a 3D point set (principal component analysis) and the map of
-- 3D points to coordinates in that plane, so a 3D section can be drawn flat and say so.
--
--   local p = require("bsfit.projection").plane(P)   -- P: Points of dimension 3
--   local u, v = p.to2(x, y, z)                       -- in-plane coordinates
--   p.normal, p.centre, p.rms_off                      -- and the points' RMS off the plane

local M = {}

-- Eigen-decomposition of the symmetric 3x3 matrix a (a[i][j]) by cyclic Jacobi
-- rotations: returns the eigenvalues and the eigenvectors (columns of v).
local function jacobi3(a)
  local v = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } }
  for _ = 1, 50 do
    local off = a[1][2] ^ 2 + a[1][3] ^ 2 + a[2][3] ^ 2
    if off < 1e-30 * (a[1][1] ^ 2 + a[2][2] ^ 2 + a[3][3] ^ 2 + 1e-300) then break end
    for p = 1, 2 do
      for q = p + 1, 3 do
        if a[p][q] ~= 0 then
          local theta = (a[q][q] - a[p][p]) / (2 * a[p][q])
          local t = (theta >= 0 and 1 or -1) / (math.abs(theta) + math.sqrt(theta * theta + 1))
          local c = 1 / math.sqrt(t * t + 1)
          local s = t * c
          for k = 1, 3 do -- A <- A J (columns p, q)
            local akp, akq = a[k][p], a[k][q]
            a[k][p], a[k][q] = c * akp - s * akq, s * akp + c * akq
          end
          for k = 1, 3 do -- A <- J^T A (rows p, q)
            local apk, aqk = a[p][k], a[q][k]
            a[p][k], a[q][k] = c * apk - s * aqk, s * apk + c * aqk
          end
          for k = 1, 3 do
            local vkp, vkq = v[k][p], v[k][q]
            v[k][p], v[k][q] = c * vkp - s * vkq, s * vkp + c * vkq
          end
        end
      end
    end
  end
  return { a[1][1], a[2][2], a[3][3] }, v
end

-- Centroid and covariance of the points of P (dimension 3).
local function moments(P)
  local m, c = #P, { 0, 0, 0 }
  for i = 1, m do
    local x, y, z = P:get(i)
    c[1], c[2], c[3] = c[1] + x, c[2] + y, c[3] + z
  end
  for k = 1, 3 do c[k] = c[k] / m end
  local a = { { 0, 0, 0 }, { 0, 0, 0 }, { 0, 0, 0 } }
  for i = 1, m do
    local d = { P:get(i) }
    for r = 1, 3 do
      d[r] = d[r] - c[r]
    end
    for r = 1, 3 do for s = r, 3 do a[r][s] = a[r][s] + d[r] * d[s] end end
  end
  for r = 1, 3 do for s = r, 3 do a[r][s] = a[r][s] / m; a[s][r] = a[r][s] end end
  return c, a
end

-- The plane of P: e1, e2 (unit, the two largest principal directions), normal,
-- centre, rms_off (RMS distance of the points to the plane) and to2(x, y, z).
function M.plane(P)
  local c, a = moments(P)
  local lam, v = jacobi3(a)
  local order = { 1, 2, 3 }
  table.sort(order, function(i, j) return lam[i] > lam[j] end)
  local function col(k) return { v[1][k], v[2][k], v[3][k] } end
  local e1, e2, n = col(order[1]), col(order[2]), col(order[3])
  local p = { e1 = e1, e2 = e2, normal = n, centre = c,
              rms_off = math.sqrt(math.max(0, lam[order[3]])) }
  function p.to2(x, y, z)
    local dx, dy, dz = x - c[1], y - c[2], (z or 0) - c[3]
    return dx * e1[1] + dy * e1[2] + dz * e1[3], dx * e2[1] + dy * e2[2] + dz * e2[3]
  end
  return p
end

return M
