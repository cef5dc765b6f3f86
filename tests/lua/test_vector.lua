-- test_vector.lua: bsfit.Vector
local T = require "tap"
local bs = require "bsfit"

T.test("new from a table, get, set, #, totable", function()
  local v = bs.vector.new{3, 1.5, -2}
  T.eq(#v, 3)
  T.eq(v:get(1), 3); T.eq(v:get(-1), -2)
  T.eq(v:set(2, 10), v, "set returns self")
  local t = v:totable()
  T.eq(#t, 3); T.eq(t[2], 10)
end)

T.test("new(n [, fill])", function()
  local v = bs.vector.new(5)
  for i = 1, 5 do T.eq(v:get(i), 0) end
  local w = bs.vector.new(4, 2.5)
  T.eq(w:sum(), 10)
  T.eq(#bs.vector.new(0), 0)
end)

T.test("sum, max, min with their 1-based index", function()
  local v = bs.vector.new{1, 7, -3, 7, 2}
  T.eq(v:sum(), 14)
  local m, i = v:max()
  T.eq(m, 7); T.eq(i, 2, "first index on ties")
  m, i = v:min()
  T.eq(m, -3); T.eq(i, 3)
  T.eq(bs.vector.new(0):max(), nil)
  -- sum of 1..n is n(n+1)/2
  local n = 1000
  local u = bs.vector.new(n)
  for k = 1, n do u:set(k, k) end
  T.eq(u:sum(), n * (n + 1) / 2)
end)

T.test("rms: plain, weighted, winsorised; bad arguments", function()
  local v = bs.vector.new{3, -4}
  T.near(v:rms(), math.sqrt(12.5), 1e-15) -- (9 + 16) / 2
  T.near(v:rms(bs.vector.new{1, 0}), 3, 1e-15, "zero weight drops a value")
  T.near(v:rms(bs.vector.new{1, 3}), math.sqrt((9 + 48) / 4), 1e-15)
  T.near(v:rms(nil, 2), 2, 1e-15, "both clipped at 2")
  T.eq(bs.vector.new(0):rms(), 0)
  T.raises("bad argument #1 to 'rms' (2 weights for 3 values)", function() bs.vector.new{1, 2, 3}:rms(v) end)
  T.raises("bad argument #2 to 'rms' (clip must be positive)", function() v:rms(nil, 0) end)
  T.raises({ match = "bad argument #1 to 'rms' %(bsfit.Vector expected" }, function() v:rms({1, 2}) end)
end)

T.test("bytes/frombytes and copy", function()
  local v = bs.vector.new{1, 2, 3}
  T.eq(v:bytes(), string.pack("=ddd", 1, 2, 3))
  local w = bs.vector.frombytes(v:bytes())
  T.eq(#w, 3); T.eq(w:get(3), 3)
  local c = v:copy(); c:set(1, 9)
  T.eq(v:get(1), 1, "copy is deep")
  T.ok(tostring(v):match("^bsfit%.Vector%(n=3%): "))
end)

T.test("bad inputs raise naming the argument", function()
  T.raises("bad argument #1 to 'new' (element 2 is not a number)", function() bs.vector.new{1, "a"} end)
  local v = bs.vector.new{1}
  T.raises("bad argument #1 to 'get' (index 2 out of range 1..1)", function() v:get(2) end)
  T.raises("bad argument #2 to 'set' (number expected, got string)", function() v:set(1, "x") end)
  T.raises("bad argument #1 to 'frombytes' (length is not a multiple of 8)", function() bs.vector.frombytes("abc") end)
  local P = bs.points.new(1, 2)
  T.raises("bad argument #1 to 'sum' (bsfit.Vector expected, got bsfit.Points)", function() v.sum(P) end)
end)
