-- test_skin.lua: bs.surface.skin (src/lua/lskin.c) and the CAD exchange writers seen from
-- Lua (C:write / S:write to .step, .dxf, .obj; bs.io.write_step / write_dxf). The surface
-- is checked against its sections by evaluation (every section, at many parameters,
-- through the report's v_params, shifts and reversed), against a cone it must contain
-- exactly (linear sections across), and the error contract with 1-based names.
local T = require "tap"
local bs = require "bsfit"

-- a closed cubic through n points of an ellipse at height z, starting at angle theta
local function section(z, ax, ay, n, theta, reverse)
  local P = {}
  for i = 1, n do
    local a = (theta or 0) + (reverse and -1 or 1) * 2 * math.pi * (i - 1) / n
    P[i] = { ax * math.cos(a), ay * math.sin(a), z }
  end
  return bs.curve.new { degree = 3, periodic = true, control_points = P }
end

local function dist(x1, y1, z1, x2, y2, z2)
  return math.sqrt((x1 - x2) ^ 2 + (y1 - y2) ^ 2 + (z1 - z2) ^ 2)
end

-- the largest |S(u, v_k) - C_k(t_k(u))| over the sections, t_k from the report
local function section_error(S, rep, sections)
  local worst = 0
  for k, C in ipairs(sections) do
    local a, b = C:domain()
    for i = 0, 99 do
      local u = i / 100
      local t = rep.reversed[k] and rep.shifts[k] - (b - a) * u or rep.shifts[k] + (b - a) * u
      local x, y, z = S:eval(u, rep.v_params[k])
      worst = math.max(worst, dist(x, y, z, C:eval(t)))
    end
  end
  return worst
end

T.test("skin: the surface passes through every section (seeded random stacks)", function()
  math.randomseed(15)
  for _ = 1, 20 do
    local K, sections = math.random(2, 6), {}
    for k = 1, K do
      sections[k] = section(3 * k, math.random() * 3 + 2, math.random() * 3 + 2, math.random(5, 12),
        math.random() * 6, k > 1 and math.random() < 0.4)
    end
    local S, rep = bs.surface.skin(sections, { degree_v = math.min(K - 1, math.random(1, 3)) })
    T.eq(#rep.v_params, K)
    T.eq(rep.v_params[1], 0)
    T.eq(rep.v_params[K], 1)
    for k = 2, K do T.ok(rep.v_params[k] > rep.v_params[k - 1]) end
    T.ok(section_error(S, rep, sections) < 1e-12 * 20, "sections interpolated")
    T.eq(S:is_periodic(), true)
    local ua, ub, va, vb = S:domain()
    T.eq(ua, 0); T.eq(ub, 1); T.eq(va, 0); T.eq(vb, 1)
  end
end)

T.test("skin: two similar sections give a cone, exactly linear across", function()
  local lo, hi = section(0, 2, 2, 8), section(10, 5, 5, 8)
  local S, rep = bs.surface.skin { lo, hi }
  T.eq(S:degree(), 3)
  for i = 0, 20 do
    for j = 0, 10 do
      local u, v = i / 20, j / 10
      local x, y, z = S:eval(u, v)
      local x0, y0, z0 = S:eval(u, 0)
      local x1, y1, z1 = S:eval(u, 1)
      T.near(dist(x, y, z, (1 - v) * x0 + v * x1, (1 - v) * y0 + v * y1, (1 - v) * z0 + v * z1), 0, 1e-12)
    end
  end
  T.eq(rep.reversed[2], false)
end)

T.test("skin: twisted inputs are untwisted (align) or left as given (align = false)", function()
  local aligned, twisted = {}, {}
  for k = 1, 12 do
    local z = (k - 1) * 0.6
    aligned[k] = section(z, 4 + math.sin(z), 2.5 + 0.4 * math.cos(z), 48)
    twisted[k] = section(z, 4 + math.sin(z), 2.5 + 0.4 * math.cos(z), 48, k > 1 and k * 1.3 or 0, k % 3 == 0)
  end
  local A = bs.surface.skin(aligned)
  local B, rep = bs.surface.skin(twisted)
  local C = bs.surface.skin(twisted, { align = false })
  local ab, ac = 0, 0
  for i = 0, 49 do
    for j = 0, 19 do
      local u, v = i / 50, j / 19
      local x, y, z = A:eval(u, v)
      ab = math.max(ab, dist(x, y, z, B:eval(u, v)))
      ac = math.max(ac, dist(x, y, z, C:eval(u, v)))
    end
  end
  T.ok(ab < 1e-3, "twisted + align: the aligned surface (" .. ab .. ")")
  T.ok(ac > 1, "align = false keeps the twist (" .. ac .. ")")
  for k = 1, 12 do T.eq(rep.reversed[k], k % 3 == 0) end
end)

-- The largest distance from S(u, v_k) to section k over 400 u (closest points; the cubic
-- that replaces a section with tol follows it at chord-length parameters, not its own)
-- and from 400 points of each section to S(., v_k) (the nearest of 4000 points, refined by
-- golden sections).
local function section_distance(S, rep, sections)
  local worst = 0
  for k, C in ipairs(sections) do
    local P, Q = {}, {}
    for i = 0, 399 do P[i + 1] = { S:eval(i / 400, rep.v_params[k]) } end
    local _, d = C:closest_many(bs.points.new(P))
    for i = 1, #P do worst = math.max(worst, d:get(i)) end
    for i = 0, 3999 do Q[i + 1] = { S:eval(i / 4000, rep.v_params[k]) } end
    local a, b = C:domain()
    for i = 0, 399 do
      local x, y, z = C:eval(a + (b - a) * (i + 0.5) / 400)
      local near, at = math.huge, 0
      for j, q in ipairs(Q) do
        local e = dist(x, y, z, q[1], q[2], q[3])
        if e < near then near, at = e, j end
      end
      local function f(u) return dist(x, y, z, S:eval(u % 1, rep.v_params[k])) end
      local lo, hi, g = (at - 2) / 4000, at / 4000, (math.sqrt(5) - 1) / 2
      for _ = 1, 60 do
        local c, d = hi - g * (hi - lo), lo + g * (hi - lo)
        if f(c) < f(d) then hi = d else lo = c end
      end
      worst = math.max(worst, math.min(near, f((lo + hi) / 2)))
    end
  end
  return worst
end

T.test("skin: tol gives uniform cubics within it, and says so in the report", function()
  -- ellipses through 48 points each (48 knots per section, starts rotated): a 1e-3 skin
  local secs = {}
  for k = 1, 6 do secs[k] = section(k, 4 + 0.3 * k, 2.5, 48, 0.7 * k) end
  local E, erep = bs.surface.skin(secs)
  local L, lrep = bs.surface.skin(secs, { tol = 1e-3 })
  T.ok(erep.count == nil and lrep.count > 0, "count only with tol")
  T.ok(lrep.max_deviation <= 1e-3, "max_deviation " .. lrep.max_deviation)
  T.eq((L:count()), lrep.count + 3)
  T.ok((L:count()) < (E:count()), "lighter")
  local worst = section_distance(L, lrep, secs)
  T.ok(worst <= lrep.max_deviation * (1 + 1e-6), "every section within its max_deviation: " .. worst)
end)

T.test("skin: misuse raises naming the section from 1; coincident sections fail", function()
  local a, b = section(0, 2, 2, 8), section(1, 2, 2, 8)
  local open = bs.curve.new { degree = 2, control_points = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 } } }
  local flat = bs.curve.new { degree = 2, periodic = true, control_points = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } } }
  local rat = bs.curve.new { degree = 2, periodic = true, weights = { 1, 2, 1, 2 },
    control_points = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 } } }
  T.raises("bad argument #1 to 'skin' (a list of at least 2 sections expected)", function() bs.surface.skin { a } end)
  T.raises("bad argument #1 to 'skin' (section 2 is open (skinning needs closed, periodic sections))",
    function() bs.surface.skin { a, open } end)
  T.raises("bad argument #1 to 'skin' (section 3 is not 3D (map 2D sections to their planes first))",
    function() bs.surface.skin { a, b, flat } end)
  T.raises("bad argument #1 to 'skin' (section 2 is rational (skinning needs polynomial sections))",
    function() bs.surface.skin { a, rat } end)
  T.raises("bad argument #1 to 'skin' (section 2 is a number, not a bsfit.Curve)", function() bs.surface.skin { a, 3 } end)
  T.raises("bad argument #2 to 'skin' (field 'degree_v' must be in 1..1 (2 sections))",
    function() bs.surface.skin({ a, b }, { degree_v = 2 }) end)
  T.raises("bad argument #2 to 'skin' (unknown option 'degree')", function() bs.surface.skin({ a, b }, { degree = 2 }) end)
  T.raises("bad argument #2 to 'skin' (field 'tol' must be 0 (exact) or positive)",
    function() bs.surface.skin({ a, b }, { tol = -1 }) end)
  T.raises("bad argument #2 to 'skin' (field 'tol' must be 0 (exact) or positive)",
    function() bs.surface.skin({ a, b }, { tol = 0 / 0 }) end)
  local msg = T.fails("EDEGENERATE", bs.surface.skin, { a, b, b })
  T.eq(msg, "sections 2 and 3 coincide")
end)

T.test("writers: .step, .dxf, .obj and bs.io lists, with their errors", function()
  local base = os.tmpname()
  local C2 = bs.curve.new { degree = 2, periodic = true, control_points = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } } }
  local C3 = section(0, 2, 1, 7)
  local S = bs.surface.skin { section(0, 2, 2, 8), section(2, 3, 3, 9) }
  T.eq(C2:write(base .. ".step"), C2)
  T.eq(C3:write(base .. ".dxf"), C3)
  T.eq(S:write(base .. ".step"), S)
  T.eq(S:write(base .. ".obj", { samples_u = 10, samples_v = 4 }), S)
  T.eq(bs.io.write_step({ C2, C3 }, base .. ".all.step"), true)
  T.eq(bs.io.write_dxf({ C2, C3 }, base .. ".all.dxf"), true)
  local f = assert(io.open(base .. ".obj"))
  local text = f:read("a")
  f:close()
  local _, nv = text:gsub("\nv ", "")
  local _, nf = text:gsub("\nf ", "")
  T.eq(nv, 40)
  T.eq(nf, 2 * 10 * 3) -- closed around u: 10 columns of cells
  f = assert(io.open(base .. ".all.step"))
  text = f:read("a")
  f:close()
  local _, ncurves = text:gsub("B_SPLINE_CURVE_WITH_KNOTS%('curve", "")
  T.eq(ncurves, 2)
  local line = bs.curve.new { degree = 1, control_points = { { 0 }, { 1 } } }
  T.raises("bad argument #1 to 'write' (STEP holds 2D and 3D curves of degree >= 1, this one has dim 1, degree 1)",
    function() line:write(base .. ".step") end)
  T.raises("bad argument #1 to 'write_step' (curve 2 (dim 1, degree 1): STEP holds 2D and 3D curves of degree >= 1)",
    function() bs.io.write_step({ C2, line }, base .. ".x.step") end)
  T.raises("bad argument #1 to 'write_dxf' (item 2 is a string, not a bsfit.Curve)",
    function() bs.io.write_dxf({ C2, "x" }, base .. ".x.dxf") end)
  T.raises("bad argument #1 to 'write_step' (a non-empty list of curves expected)",
    function() bs.io.write_step({}, base .. ".x.step") end)
  T.fails("EIO", C3.write, C3, "/nonexistent-dir/x.step")
  T.fails("EIO", bs.io.write_dxf, { C3 }, "/nonexistent-dir/x.dxf")
  for _, ext in ipairs { ".step", ".dxf", ".obj", ".all.step", ".all.dxf", "" } do os.remove(base .. ext) end
end)
