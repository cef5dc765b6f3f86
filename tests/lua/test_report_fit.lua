-- test_report_fit.lua: strategy reports carry the fitter's rcond and solver, and
-- Vector:distinct (the C count behind common.distinct_params) agrees with a plain Lua
-- count on generated vectors.
local T = require "tap"
local bs = require "bsfit"
local synth = require "synth"

local SRC = (arg and arg[1] or ""):match("^(.*)/tests/lua/[^/]*$")
            or os.getenv("BSFIT_SOURCE_DIR") or "."

-- the reference: runs of equal consecutive values, counted in Lua (a NaN equals nothing)
local function runs(t)
  local n = 0
  for i = 1, #t do
    if i == 1 or t[i] ~= t[i - 1] then n = n + 1 end
  end
  return n
end

T.test("Vector:distinct counts what a plain Lua loop counts", function()
  local uniform = synth.rng(77)
  local cases = 0
  for _, m in ipairs { 0, 1, 2, 3, 7, 40, 513 } do
    for _, levels in ipairs { 1, 2, 5, 1000 } do
      for _, sorted in ipairs { true, false } do
        local t = {}
        for i = 1, m do t[i] = math.floor(uniform() * levels) / levels end
        if sorted then table.sort(t) end
        if m > 2 and levels == 5 then t[2] = 0 / 0 end -- NaNs count one each
        T.eq(bs.vector.new(t):distinct(), runs(t), ("m %d, %d levels"):format(m, levels))
        cases = cases + 1
      end
    end
  end
  T.ok(cases == 56, "every case ran")
end)

T.test("common.distinct_params: the same count from a Vector and from a table", function()
  local common = require "bsfit.strategy.common"
  for _, shape in pairs(synth.smooth) do
    local P = bs.points.new(synth.sample_smooth(shape, 30, true))
    local u = bs.params(P, "chord")
    T.eq(common.distinct_params(u), runs(u:totable()))
    T.eq(common.distinct_params(u:totable()), runs(u:totable()))
  end
end)

T.test("every strategy reports the fitter's rcond and the solver that answered", function()
  for _, s in ipairs { "auto", "periodic", "carvalho" } do
    local st, fitted, runs_ = require("bsfit.strategy." .. s), 0, 0
    for name, shape in pairs(synth.smooth) do
      for _, m in ipairs { 30, 120 } do
        for _, sigma in ipairs { 0, 0.01, 0.03 } do
          local P = synth.noisy(synth.sample_smooth(shape, m, m % 2 == 0), sigma, m)
          for _, solver in ipairs { "cholesky", "qr" } do
            local what = ("%s %s m=%d sigma=%g %s"):format(s, name, m, sigma, solver)
            local _, rep = st.run(P, { solver = solver })
            runs_ = runs_ + 1
            -- auto builds circles and lines as exact arcs and segments, without a
            -- weighted fit: there no rcond; the others always fit
            if s ~= "auto" or rep.rcond ~= nil then
              fitted = fitted + 1
              T.ok(type(rep.rcond) == "number" and rep.rcond > 0 and rep.rcond <= 1,
                   what .. ": rcond in (0, 1], got " .. tostring(rep.rcond))
              T.eq(rep.solver, solver, what)
            else
              T.eq(rep.solver, nil, what .. ": a solver without an rcond")
            end
          end
        end
      end
    end
    T.ok(fitted >= runs_ // 3, ("%s: %d of %d runs made a fit"):format(s, fitted, runs_))
  end
end)

T.test("a run without a least-squares fit reports no rcond, not the previous run's", function()
  -- the bracket is exact lines and arcs: auto builds it without a weighted fit
  local P = assert(bs.points.read(SRC .. "/tests/data/demo/bracket.csv"))
  local _, before = require("bsfit.strategy.periodic").run(P)
  T.ok(before.rcond ~= nil, "periodic fits")
  local _, rep = require("bsfit.strategy.auto").run(P)
  T.eq(rep.rcond, nil)
  T.eq(rep.solver, nil)
end)
