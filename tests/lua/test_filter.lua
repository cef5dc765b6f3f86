-- test_filter.lua: bs.filter.box against its definition (F-4),
--   C_F(t) = 1/(2 delta) * integral of C_ext over [t - delta, t + delta],
-- computed here by Simpson's rule on each polynomial piece of the integrand (the
-- window is cut at every knot, so each piece is a polynomial of degree <= 3 and
-- Simpson is exact for it up to rounding). C_ext is C on its domain and, for a
-- clamped curve, its end point beyond it (src/bsfit_filter.h). Surfaces likewise,
-- with the 2D tensor Simpson rule on each knot rectangle.
local T = require "tap"
local bs = require "bsfit"

-- the sorted cut points of [lo, hi]: its ends and every knot (shifted by `period`
-- copies for a closed curve) strictly inside
local function cuts(lo, hi, knots, period)
  local c = {lo, hi}
  for _, k in ipairs(knots) do
    for j = -2, 2 do
      local x = k + j * (period or 0)
      if x > lo and x < hi then c[#c + 1] = x end
      if not period then break end
    end
  end
  table.sort(c)
  return c
end

-- mean of f (returning dim numbers) over [lo, hi], exact for piecewise cubics with
-- breaks at `knots`: 2 Simpson panels per piece
local function mean1(f, lo, hi, knots, period, dim)
  local c, s = cuts(lo, hi, knots, period), {}
  for k = 1, dim do s[k] = 0 end
  for i = 1, #c - 1 do
    local a, b = c[i], c[i + 1]
    local h = (b - a) / 4
    for j = 0, 4 do
      local wgt = (j == 0 or j == 4) and 1 or (j % 2 == 1 and 4 or 2)
      local x = {f(a + j * h)}
      for k = 1, dim do s[k] = s[k] + wgt * h / 3 * x[k] end
    end
  end
  for k = 1, dim do s[k] = s[k] / (hi - lo) end
  return s
end

-- C_ext of a clamped open curve: constant beyond its domain
local function extended(C)
  local a, b = C:domain()
  return function(u) return C:eval(math.min(math.max(u, a), b)) end
end

local function check_curve(F, C, delta, ts, tol, what)
  local knots, period = C:knots():values(), nil
  if C:is_periodic() then
    local a, b = C:domain()
    period = b - a
  end
  local f = C:is_periodic() and function(u) return C:eval(u) end or extended(C)
  for _, t in ipairs(ts) do
    local want = mean1(f, t - delta, t + delta, knots, period, C:dim())
    local got = {F:eval(t)}
    for k = 1, C:dim() do T.near(got[k], want[k], tol, string.format("%s coord %d at t = %g", what, k, t)) end
  end
end

T.test("moving average of a uniform cubic (Theorem 2) equals the integral (F-4)", function()
  local Q = {{0, 0}, {1, 2}, {2, -1}, {3, 3}, {4, 0}, {5, 1}, {6, 2}}
  local K = bs.knots.uniform{degree = 3, count = #Q, domain = {0, 4}}
  local C = bs.curve.new{degree = 3, knots = K, control_points = Q}
  for _, k in ipairs{1, 2, 3} do
    local F = bs.filter.box(C, k)
    T.eq(F:degree(), 4); T.eq(C:degree(), 3, "input unchanged")
    check_curve(F, C, k / 2, {1.5, 1.77, 2.0, 2.31, 2.5}, 1e-12, "k = " .. k)
  end
end)

T.test("exact filter {delta = d} equals the integral (F-4) on uniform, clamped, non-uniform, closed curves", function()
  local Q = {{0, 0}, {1, 2}, {2, -1}, {3, 3}, {4, 0}, {5, 1}, {6, 2}}
  local U = bs.curve.new{degree = 3, knots = bs.knots.uniform{degree = 3, count = #Q, domain = {0, 4}},
                         control_points = Q}
  local Fd, Fk = bs.filter.box(U, {delta = 1}), bs.filter.box(U, 2)
  T.eq(Fd:degree(), 4); T.eq(Fd:kind(), "bspline")
  check_curve(Fd, U, 1, {1.0, 1.3, 2.0, 2.71, 3.0}, 1e-8, "uniform")
  for _, t in ipairs{1.0, 1.6, 2.9} do -- the moving average is the same function of t
    local x1, y1 = Fd:eval(t)
    local x2, y2 = Fk:eval(t)
    T.near(x1, x2, 1e-12); T.near(y1, y2, 1e-12)
  end
  -- clamped and non-uniform, the window reaching past both ends (constant extension)
  local N = bs.curve.new{degree = 3, knots = {0, 0, 0, 0, 0.1, 0.15, 0.6, 0.8, 1, 1, 1, 1},
                         control_points = {{0, 0}, {1, 3}, {2, -1}, {4, 2}, {5, 0}, {6, 1}, {7, 3}, {8, 0}}}
  for _, d in ipairs{0.02, 0.13, 0.4} do
    local F = bs.filter.box(N, {delta = d})
    local a, b = F:domain()
    T.near(a, -d, 1e-14, "filtered domain starts at a - delta"); T.near(b, 1 + d, 1e-14)
    check_curve(F, N, d, {-d, -d / 2, 0, 0.05, 0.12, 0.33, 0.61, 0.9, 1, 1 + d}, 1e-8, "delta " .. d)
  end
  -- 3D, quadratic
  local S = bs.curve.new{degree = 2, knots = {0, 0, 0, 0.3, 0.5, 1, 1, 1},
                         control_points = {{0, 0, 0}, {1, 1, 2}, {2, 0, 1}, {3, 2, 0}, {4, 1, 1}}}
  check_curve(bs.filter.box(S, {delta = 0.1}), S, 0.1, {0.05, 0.3, 0.42, 0.77}, 1e-8, "3D quadratic")
  -- closed: the window wraps around the seam
  local P = bs.curve.new{degree = 3, periodic = true, knots = {0, 0.1, 0.35, 0.5, 0.8, 1},
                         control_points = {{0, 0}, {2, -1}, {3, 1}, {2, 3}, {-1, 2}}}
  for _, d in ipairs{0.05, 0.2} do
    local F = bs.filter.box(P, {delta = d})
    T.ok(F:is_periodic(), "closed stays closed")
    check_curve(F, P, d, {0, 0.03, 0.25, 0.5, 0.97}, 1e-8, "closed delta " .. d)
  end
end)

T.test("filter misuse raises with the argument named", function()
  local C = bs.curve.new{degree = 3, knots = bs.knots.uniform{degree = 3, count = 6}, control_points =
                         {{0, 0}, {1, 2}, {2, -1}, {3, 3}, {4, 0}, {5, 1}}}
  T.raises("bad argument #2 to 'box' (window width must be at least 1)", function() bs.filter.box(C, 0) end)
  T.raises("bad argument #2 to 'box' (unknown option 'width')", function() bs.filter.box(C, {width = 1}) end)
  T.raises("bad argument #2 to 'box' (field 'delta' must be a number)", function() bs.filter.box(C, {delta = "1"}) end)
  T.raises("bad argument #2 to 'box' (field 'delta' is required)", function() bs.filter.box(C, {}) end)
  T.raises({match = "^bad argument #2 to 'box' %(.*delta"}, function() bs.filter.box(C, {delta = 0 / 0}) end)
  T.raises({match = "^bad argument #2 to 'box' %(.*delta"}, function() bs.filter.box(C, {delta = -1}) end)
  T.raises({match = "^bad argument #2 to 'box' %(.*uniform"},
           function() bs.filter.box(bs.curve.new{degree = 2, control_points = {{0, 0}, {1, 1}, {2, 0}, {3, 1}}}, 1) end)
  T.raises({match = "^bad argument #2 to 'box' %(.*rational"},
           function() bs.filter.box(bs.curve.new{degree = 1, control_points = {{0, 0}, {1, 1}}, weights = {1, 2}},
                                    {delta = 0.1}) end)
  T.raises("bad argument #1 to 'box' (bsfit.Curve or bsfit.Surface expected, got number)",
           function() bs.filter.box(3, 1) end)
  T.raises("bad argument #1 to 'box' (bsfit.Curve or bsfit.Surface expected, got bsfit.Points)",
           function() bs.filter.box(bs.points.new(2, 2), 1) end)
end)

-- {{{x,y,z}...}...}: a bumpy height field over a nu x nv grid
local function net(nu, nv)
  local rows = {}
  for i = 1, nu do
    rows[i] = {}
    for j = 1, nv do rows[i][j] = {i, j, math.sin(i * 1.3) * math.cos(j * 0.7) + 0.1 * i * j} end
  end
  return rows
end

-- mean of S over [u-du, u+du] x [v-dv, v+dv] (inside the domain): tensor Simpson,
-- 2 panels per direction on each knot rectangle
local function mean2(S, u, v, du, dv)
  local cu, cv = cuts(u - du, u + du, S:knots_u():values()), cuts(v - dv, v + dv, S:knots_v():values())
  local s = {0, 0, 0}
  for a = 1, #cu - 1 do
    local hu = (cu[a + 1] - cu[a]) / 2
    for b = 1, #cv - 1 do
      local hv = (cv[b + 1] - cv[b]) / 2
      for i = 0, 2 do
        for j = 0, 2 do
          local w = (i == 1 and 4 or 1) * (j == 1 and 4 or 1) * hu * hv / 9
          local p = {S:eval(cu[a] + i * hu, cv[b] + j * hv)}
          for k = 1, 3 do s[k] = s[k] + w * p[k] end
        end
      end
    end
  end
  for k = 1, 3 do s[k] = s[k] / (4 * du * dv) end
  return s
end

T.test("surfaces: the k x l moving average and the exact filter equal the 2D integral", function()
  local S = bs.surface.new{degree_u = 3, degree_v = 2, control_points = net(8, 7),
                           knots_u = bs.knots.uniform{degree = 3, count = 8, domain = {0, 5}},
                           knots_v = bs.knots.uniform{degree = 2, count = 7, domain = {0, 5}}}
  local F = bs.filter.box(S, 2, 3) -- 2 delta_u = 2 spans of 1, 2 delta_v = 3 spans of 1
  T.eq(select(1, F:degree()), 4); T.eq(select(2, F:degree()), 3)
  local E = bs.filter.box(S, {delta_u = 1, delta_v = 1.5})
  for _, uv in ipairs{{1.5, 1.7}, {2.2, 2.5}, {3.4, 3.1}, {2.5, 2.5}} do
    local want = mean2(S, uv[1], uv[2], 1, 1.5)
    local a, b = {F:eval(uv[1], uv[2])}, {E:eval(uv[1], uv[2])}
    for k = 1, 3 do
      T.near(a[k], want[k], 1e-10, "moving average " .. k)
      T.near(b[k], want[k], 1e-8, "exact " .. k)
    end
  end
  -- a clamped non-uniform surface with the exact filter
  local C = bs.surface.new{degree_u = 2, degree_v = 2, control_points = net(5, 4),
                           knots_u = {0, 0, 0, 0.2, 0.7, 1, 1, 1}, knots_v = {0, 0, 0, 0.4, 1, 1, 1}}
  local G = bs.filter.box(C, {delta_u = 0.1, delta_v = 0.15})
  for _, uv in ipairs{{0.3, 0.3}, {0.5, 0.6}, {0.75, 0.2}} do
    local want = mean2(C, uv[1], uv[2], 0.1, 0.15)
    local got = {G:eval(uv[1], uv[2])}
    for k = 1, 3 do T.near(got[k], want[k], 1e-8, "clamped surface " .. k) end
  end
  T.raises("bad argument #3 to 'box' (window width must be at least 1)", function() bs.filter.box(S, 1, 0) end)
  T.raises("bad argument #2 to 'box' (field 'delta_v' is required)", function() bs.filter.box(S, {delta_u = 1}) end)
  T.raises("bad argument #2 to 'box' (unknown option 'delta')", function() bs.filter.box(S, {delta = 1}) end)
  T.raises({match = "^bad argument #2 to 'box' %(knot spans are not all equal"}, function() bs.filter.box(C, 1, 1) end)
end)
