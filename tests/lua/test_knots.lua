-- test_knots.lua: bsfit.Knots (kinds, span search, validation)
local T = require "tap"
local bs = require "bsfit"

local function same(got, want, msg)
  T.eq(#got, #want, (msg or "") .. " length")
  for i = 1, #want do T.near(got[i], want[i], 1e-15, (msg or "") .. " knot " .. i) end
end

T.test("clamped: p+1 end copies and equal interior spans (NURBS Book open uniform)", function()
  local K = bs.knots.clamped{degree = 3, count = 7}
  same(K:values(), {0, 0, 0, 0, 0.25, 0.5, 0.75, 1, 1, 1, 1}, "clamped")
  T.eq(#K, 11); T.eq(K:degree(), 3); T.eq(K:count(), 7)
  local a, b = K:domain()
  T.eq(a, 0); T.eq(b, 1)
  T.eq(K:multiplicity(0), 4); T.eq(K:multiplicity(0.5), 1); T.eq(K:multiplicity(0.3), 0)
end)

T.test("uniform: U[i] = a + (i-p) h on the requested domain", function()
  local K = bs.knots.uniform{degree = 2, count = 5, domain = {0, 3}}
  same(K:values(), {-2, -1, 0, 1, 2, 3, 4, 5}, "uniform")
  local a, b = K:domain()
  T.eq(a, 0); T.eq(b, 3)
end)

T.test("periodic: spans repeat around one period (docs/method.md §1)", function()
  local K = bs.knots.periodic{degree = 3, count = 4}
  same(K:values(), {-0.75, -0.5, -0.25, 0, 0.25, 0.5, 0.75, 1, 1.25, 1.5, 1.75}, "uniform periodic")
  local P = bs.knots.periodic{degree = 2, period = {0, 0.1, 0.5, 1}}
  same(P:values(), {-0.9, -0.5, 0, 0.1, 0.5, 1, 1.1, 1.5}, "non-uniform periodic")
end)

T.test("span: K[i] <= t < K[i+1], ends folded into the domain's spans", function()
  local K = bs.knots.new{degree = 2, values = {0, 0, 0, 1, 2, 2, 3, 3, 3}}
  local U = K:values()
  for _, t in ipairs{0, 0.5, 1, 1.5, 1.999, 2, 2.5} do
    local i = K:span(t)
    T.ok(U[i] <= t and t < U[i + 1], "span of " .. t .. " is " .. i)
  end
  T.eq(K:span(3), 6, "domain end evaluates from the left: last non-empty span")
  T.eq(K:span(-1), 3, "before the domain: first span")
  T.eq(K:get(4), 1); T.eq(K:get(-1), 3)
  local v = K:vector()
  T.eq(#v, 9); T.eq(v:get(5), 2)
end)

T.test("values are validated: monotone, finite, multiplicity, size", function()
  T.raises("bad argument #1 to 'new' (knots decrease at knot 5 (0.5 < 1))",
           function() bs.knots.new{degree = 1, values = {0, 0, 1, 1, 0.5, 2}} end)
  T.raises("bad argument #1 to 'new' (knot 3 is not finite)",
           function() bs.knots.new{degree = 1, values = {0, 0, 0 / 0, 1}} end)
  T.raises("bad argument #1 to 'new' (knots 1..3 equal 0: multiplicity above degree+1 = 2)",
           function() bs.knots.new{degree = 1, values = {0, 0, 0, 1, 1}} end)
  T.raises("bad argument #1 to 'new' (degree 3 needs at least 8 knots, got 5)",
           function() bs.knots.new{degree = 3, values = {0, 0, 0, 1, 1}} end)
  T.raises("bad argument #1 to 'new' (field 'degree' is required)",
           function() bs.knots.new{values = {0, 1}} end)
  T.raises("bad argument #1 to 'new' (field 'degree' must be an integer)",
           function() bs.knots.new{degree = "3", values = {0, 1}} end)
  T.raises("bad argument #1 to 'new' (unknown option 'degre')",
           function() bs.knots.new{degre = 3, values = {0, 1}} end)
  T.raises("bad argument #1 to 'new' (field 'values' must be a table or bsfit.Vector)",
           function() bs.knots.new{degree = 1, values = 5} end)
  T.raises("bad argument #1 to 'clamped' (field 'count' must be at least degree+1 = 4)",
           function() bs.knots.clamped{degree = 3, count = 3} end)
  T.raises("bad argument #1 to 'uniform' (field 'domain' must be a table {a, b})",
           function() bs.knots.uniform{degree = 1, count = 3, domain = 5} end)
  T.raises("bad argument #1 to 'uniform' (domain [1, 0] must be finite with a < b)",
           function() bs.knots.uniform{degree = 1, count = 3, domain = {1, 0}} end)
  local K = bs.knots.clamped{degree = 1, count = 2}
  T.raises("bad argument #1 to 'span' (parameter is not finite)", function() K:span(0 / 0) end)
end)
