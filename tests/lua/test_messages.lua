-- test_messages.lua
-- Messages a Lua user sees count from 1 (knots, parameters, points, weights, knot
-- spans) and name Lua functions, never C ones (issue 13, finding 18). Bad values are
-- put at random places in random vectors, for every constructor that takes knots.
local T = require "tap"
local bs = require "bsfit"

-- A small deterministic generator (the tests must not depend on math.random's seed).
local function rng(seed)
  local s = seed
  return function(n)
    s = (s * 1103515245 + 12345) % 2147483648
    return n and (s % n) + 1 or s / 2147483648
  end
end

-- n sorted knots for degree p, clamped, interior values strictly increasing.
local function knots(r, p, nctrl)
  local U, inner = {}, nctrl - p - 1
  for _ = 1, p + 1 do U[#U + 1] = 0 end
  local x = 0
  for _ = 1, inner do x = x + 0.1 + r(); U[#U + 1] = x end
  for _ = 1, p + 1 do U[#U + 1] = x + 1 end
  return U
end

local function ctrl(n, dim)
  local P = {}
  for i = 1, n do P[i] = dim == 3 and {i, i * i % 7, 1} or {i, i * i % 7} end
  return P
end

-- The constructors that take a knot vector, each given U (degree p, n control points).
local makers = {
  ["bs.knots.new"] = function(U, p) return bs.knots.new{degree = p, values = U} end,
  ["bs.curve.new"] = function(U, p, n)
    return bs.curve.new{degree = p, knots = U, control_points = ctrl(n, 2)}
  end,
  ["bs.fitter"] = function(U, p) return bs.fitter{degree = p, knots = U} end,
  ["bs.surface.new"] = function(U, p, n)
    local net = {}
    for i = 1, n do net[i] = ctrl(2, 3) end
    return bs.surface.new{degree_u = p, degree_v = 1, knots_u = U, knots_v = {0, 0, 1, 1},
                          control_points = net}
  end,
}

local function message(fn, ...)
  local ok, err = pcall(fn, ...)
  T.ok(not ok, "the call did not raise")
  return tostring(err)
end

T.test("a non-finite knot is named by its 1-based index, by every constructor", function()
  local r = rng(11)
  for name, make in pairs(makers) do
    for _ = 1, 25 do
      local p = r(4)
      local n = p + 1 + r(8)
      local U = knots(r, p, n)
      local i = r(#U)
      U[i] = ({0 / 0, math.huge, -math.huge})[r(3)]
      local msg = message(make, U, p, n)
      T.ok(msg:find("knot " .. i .. " is not finite", 1, true), name .. ": " .. msg)
    end
  end
end)

T.test("decreasing knots are named by the 1-based index of the smaller one", function()
  local r = rng(12)
  for name, make in pairs(makers) do
    for _ = 1, 25 do
      local p = r(4)
      local n = p + 2 + r(8)
      local U = knots(r, p, n)
      local i = p + 1 + r(n - p) -- an interior or last knot, 1-based, not the first
      U[i] = U[i - 1] - 0.5
      local msg = message(make, U, p, n)
      T.ok(msg:find("knots decrease at knot " .. i .. " ", 1, true), name .. ": " .. msg)
    end
  end
end)

T.test("a knot repeated more than degree+1 times: its 1-based run and value", function()
  local r = rng(13)
  for _ = 1, 25 do
    local p = r(3)
    local n = 2 * p + 3 + r(6)
    local U = knots(r, p, n)
    local i = p + 1 + r(n - 2 * p - 2) -- start of the run, 1-based: interior knots only
    for k = i, i + p + 1 do U[k] = U[i] end -- p + 2 equal values, the next one larger
    local msg = message(makers["bs.knots.new"], U, p, n)
    T.ok(msg:find(("knots %d..%d equal %s"):format(i, i + p + 1, ("%g"):format(U[i])), 1, true),
         msg)
  end
end)

T.test("parameters for knot placement: 1-based index of the bad one", function()
  local r = rng(14)
  for _ = 1, 25 do
    local m = 6 + r(30)
    local u = {}
    for k = 1, m do u[k] = (k - 1) / (m - 1) end
    local i = 1 + r(m - 1)
    local bad = r(2) == 1
    u[i] = bad and 0 / 0 or u[i - 1] - 0.25
    local msg = message(bs.knots.averaging, {params = u, count = 4, degree = 2})
    local want = bad and ("parameter " .. i .. " is not finite")
                 or ("parameters decrease at parameter " .. i .. " ")
    T.ok(msg:find(want, 1, true), msg)
  end
end)

T.test("an empty knot span is numbered as K:span numbers it", function()
  local r = rng(15)
  local seen = 0
  for _ = 1, 25 do
    local p = r(3)
    local n = 2 * p + 2 + r(6)
    local U = knots(r, p, n)
    local K = bs.knots.new{degree = p, values = U}
    -- data everywhere but in p + 1 spans in a row (one basis function sees no data):
    -- the first of them is the 1-based span s, [U[s], U[s+1])
    local s = p + r(n - 2 * p)
    local a, b = U[p + 1], U[n + 1]
    local P, u = {}, {}
    for k = 0, 400 do
      local t = a + (b - a) * k / 400
      if not (t >= U[s] and t < U[s + p + 1]) then u[#u + 1] = t; P[#P + 1] = {t, math.sin(t)} end
    end
    local F = bs.fitter{degree = p, knots = K}
    local C, msg, code = F:fit(P, u)
    T.eq(code, "EEMPTYSPAN", msg)
    T.ok(not C)
    local mid = (U[s] + U[s + 1]) / 2
    T.ok(msg:find("knot span " .. K:span(mid) .. " ", 1, true), msg)
    seen = seen + 1
  end
  T.eq(seen, 25)
end)

T.test("no message names a C function", function()
  local C = bs.curve.new{degree = 3, control_points = ctrl(6, 2)}
  local msg = message(bs.filter.box, C, 2)
  T.ok(msg:find("bs.filter.box(C, {delta = d})", 1, true), msg)
  T.ok(not msg:find("bsfit_", 1, true), msg)
  local S = bs.surface.new{degree_u = 1, degree_v = 1, knots_u = {0, 0, 0.3, 1, 1},
                           knots_v = {0, 0, 1, 1}, control_points = {ctrl(2, 3), ctrl(2, 3),
                                                                     ctrl(2, 3)}}
  msg = message(bs.filter.box, S, 1, 1)
  T.ok(msg:find("bs.filter.box(S, {delta_u = du, delta_v = dv})", 1, true), msg)
  T.ok(not msg:find("bsfit_", 1, true), msg)
end)

return T
