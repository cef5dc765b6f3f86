-- test_scanner_input.lua: what scanners write, taken by every strategy: a closed
-- section whose last point repeats the first (dropped and reported), repeated
-- consecutive points (never an error; carvalho merges them), and the messages of
-- sections too small or degenerate (no internal file:line, no "bad argument").
local T = require "tap"
local bs = require "bsfit"
local synth = require "synth"

local STRATEGIES = { "auto", "carvalho", "periodic" }

-- Generated sections: every smooth shape, several sizes, clean and noisy, two seeds.
local function sections()
  local out = {}
  for name, f in pairs(synth.smooth) do
    for _, m in ipairs { 24, 61, 150 } do
      for _, sigma in ipairs { 0, 0.003 } do
        for seed = 1, 2 do
          local P = synth.noisy(synth.sample_smooth(f, m, seed == 2), sigma, seed * 7 + m)
          out[#out + 1] = { name = ("%s m=%d sigma=%g seed=%d"):format(name, m, sigma, seed),
                            pts = P:totable() }
        end
      end
    end
  end
  return out
end

local function copy(t)
  local r = {}
  for i, v in ipairs(t) do r[i] = { v[1], v[2] } end
  return r
end

T.test("a repeated closing point is dropped, reported, and fits as without it", function()
  for _, s in ipairs(STRATEGIES) do
    local st = require("bsfit.strategy." .. s)
    for _, sec in ipairs(sections()) do
      local m = #sec.pts
      local closedpts = copy(sec.pts)
      closedpts[m + 1] = { sec.pts[1][1], sec.pts[1][2] }
      local w = {}
      for i = 1, m do w[i] = 1 + (i % 3) end
      local wc = { table.unpack(w) }
      wc[m + 1] = 5
      local C0, r0 = st.run(bs.points.new(sec.pts), { point_weights = w })
      local C1, r1 = st.run(bs.points.new(closedpts), { point_weights = wc })
      T.ok(C0 and C1, s .. " " .. sec.name)
      T.eq(r1.dropped_closing_point, true, s .. " " .. sec.name)
      T.eq(#r1.warnings, 1, s .. " " .. sec.name)
      T.ok(r1.warnings[1]:find(("point %d repeats point 1"):format(m + 1), 1, true), r1.warnings[1])
      T.eq(r0.dropped_closing_point, nil)
      T.eq(#r0.warnings, 0)
      local a, b = C0:domain()
      for k = 0, 20 do
        local t = a + (b - a) * k / 20
        local x0, y0 = C0:eval(t)
        local x1, y1 = C1:eval(t)
        T.ok(x0 == x1 and y0 == y1, ("%s %s: the same curve at t=%g"):format(s, sec.name, t))
      end
    end
  end
end)

-- A closing point given twice or three times (a scanner that repeats its last sample) is
-- dropped as once: every strategy raised "bad argument #1 to 'params' (closed data: the
-- last point repeats the first (drop point 12))" on a 12-point circle with two repeats.
T.test("a closing point given twice or three times is dropped, and fits as without it", function()
  for _, s in ipairs(STRATEGIES) do
    local st = require("bsfit.strategy." .. s)
    for _, sec in ipairs(sections()) do
      local m = #sec.pts
      local C0 = st.run(bs.points.new(sec.pts))
      for extra = 2, 3 do
        local pts = copy(sec.pts)
        for k = 1, extra do pts[m + k] = { sec.pts[1][1], sec.pts[1][2] } end
        local what = ("%s %s, the closing point %d times"):format(s, sec.name, extra)
        local ok, C1, r1 = pcall(st.run, bs.points.new(pts))
        T.ok(ok, what .. ": " .. tostring(C1))
        T.eq(r1.dropped_closing_point, true, what)
        local said = ("points %d to %d repeat point 1"):format(m + 1, m + extra)
        T.ok(r1.warnings[1]:find(said, 1, true),
             r1.warnings[1])
        local a, b = C0:domain()
        for k = 0, 20 do
          local t = a + (b - a) * k / 20
          local x0, y0 = C0:eval(t)
          local x1, y1 = C1:eval(t)
          T.ok(x0 == x1 and y0 == y1, ("%s: the same curve at t=%g"):format(what, t))
        end
      end
    end
  end
end)

T.test("open fits keep a last point equal to the first", function()
  local pts = synth.sample_smooth(synth.smooth.ellipse, 40)
  pts[41] = { pts[1][1], pts[1][2] }
  for _, s in ipairs { "auto", "periodic" } do
    local C, rep = require("bsfit.strategy." .. s).run(bs.points.new(pts), { closed = false })
    T.ok(C, s)
    T.eq(rep.dropped_closing_point, nil, s)
    T.eq(#rep.residuals, 41, s)
  end
end)

-- Runs of 2..4 equal points at random places.
local function with_repeats(pts, seed)
  local uniform = synth.rng(seed)
  local out, first = {}, {}
  for i, p in ipairs(pts) do
    out[#out + 1] = { p[1], p[2] }
    first[#out] = #out
    if i > 1 and i < #pts and uniform() < 0.08 then
      local k = #out
      for _ = 1, 1 + math.floor(uniform() * 3) do
        out[#out + 1] = { p[1], p[2] }
        first[#out] = k
      end
    end
  end
  return out, first
end

T.test("repeated consecutive points: every strategy fits, the report in the input's terms", function()
  for _, s in ipairs(STRATEGIES) do
    local st = require("bsfit.strategy." .. s)
    for i, sec in ipairs(sections()) do
      local pts, first = with_repeats(sec.pts, i)
      local P = bs.points.new(pts)
      local ok, C, rep = pcall(st.run, P, {})
      T.ok(ok and C, ("%s %s: %s"):format(s, sec.name, tostring(ok and rep or C)))
      T.eq(#rep.residuals, #pts, s .. " " .. sec.name)
      for j = 1, #pts do
        T.ok(rep.residuals[j] == rep.residuals[first[j]], s .. ": a repeat is where its first is")
      end
      T.ok(rep.max_index >= 1 and rep.max_index <= #pts)
      -- the reported max is the distance of the reported point (closest point, independent)
      local x, y = P:get(rep.max_index)
      local _, d = C:closest(x, y)
      T.near(d, rep.max, 1e-9 * (1 + rep.max), s .. " " .. sec.name)
      T.ok(rep.start_index >= 1 and rep.start_index <= #pts)
    end
  end
end)

T.test("tiny and degenerate sections: one clear message, nothing internal", function()
  local cases = {
    { { 0, 0 } }, { { 0, 0 }, { 1, 1 } }, { { 1, 1 }, { 1, 1 }, { 1, 1 }, { 1, 1 }, { 1, 1 } },
    { { 0, 0 }, { 1, 0 }, { 0, 1 }, { 0, 0 } },
  }
  for _, s in ipairs(STRATEGIES) do
    for _, pts in ipairs(cases) do
      local ok, err = pcall(require("bsfit.strategy." .. s).run, bs.points.new(pts), {})
      T.ok(not ok, s)
      err = tostring(err)
      T.ok(not err:find("%.lua:%d") and not err:find("bad argument"), s .. ": " .. err)
      T.ok(err:find("too few") or err:find("coincide"), s .. ": " .. err)
    end
  end
end)
