-- test_explicit_requests.lua: an explicit request the data cannot honour is an error
-- naming the limit (count) or the best fit with a warning (tol), never silently
-- changed, in every strategy (checked on generated shapes, sizes and noise levels).
local T = require "tap"
local bs = require "bsfit"
local synth = require "synth"

local function sections()
  local out = {}
  for name, f in pairs(synth.smooth) do
    for _, m in ipairs { 16, 40, 90 } do
      for _, sigma in ipairs { 0, 0.01 } do
        local P = synth.noisy(synth.sample_smooth(f, m, m % 2 == 0), sigma, m + 3)
        out[#out + 1] = { name = ("%s m=%d sigma=%g"):format(name, m, sigma), P = P, m = m }
      end
    end
  end
  return out
end

T.test("count: above the points or below degree + 1 raises naming the limit", function()
  for _, s in ipairs { "auto", "carvalho", "periodic" } do
    local st = require("bsfit.strategy." .. s)
    for _, sec in ipairs(sections()) do
      for _, n in ipairs { sec.m + 1, 10 * sec.m, 1000000 } do
        T.raises(("%s: count %d is more than the %d points allow (at most %d)")
                   :format(s, n, sec.m, sec.m),
                 function() st.run(sec.P, { count = n }) end)
      end
      for _, p in ipairs { 2, 3 } do
        T.raises(("%s: count %d is below the minimum for degree %d (at least %d)")
                   :format(s, p, p, p + 1),
                 function() st.run(sec.P, { count = p, degree = p }) end)
      end
    end
  end
end)

T.test("count: every count in range is honoured exactly or refused, never changed", function()
  for _, s in ipairs { "auto", "carvalho", "periodic" } do
    local st = require("bsfit.strategy." .. s)
    for _, sec in ipairs(sections()) do
      for n = 4, sec.m, math.max(1, sec.m // 7) do
        local ok, C = pcall(st.run, sec.P, { count = n })
        if ok then
          T.eq(C:distinct(), n, ("%s %s count %d"):format(s, sec.name, n))
        else
          T.ok(tostring(C):find("cannot be honoured") or tostring(C):find("failed"),
               ("%s %s count %d: %s"):format(s, sec.name, n, tostring(C)))
        end
      end
    end
  end
end)

-- the largest closest-point distance of the points, computed point by point
local function max_distance(C, P)
  local mx = 0
  for i = 1, #P do
    local _, d = C:closest(P:get(i))
    mx = math.max(mx, d)
  end
  return mx
end

T.test("tol: met, no warning and the distance within; unmet, the best fit, a warning", function()
  for _, s in ipairs { "auto", "periodic" } do
    local st = require("bsfit.strategy." .. s)
    for _, sec in ipairs(sections()) do
      local C, rep = st.run(sec.P, { tol = 1e-300 })
      T.ok(C, s)
      T.eq(rep.tol_met, false, s .. " " .. sec.name)
      T.ok(rep.warnings[#rep.warnings]:find("^tol 1e%-300 not met: max deviation"), rep.warnings[1])
      local loose = 3 * max_distance(select(1, st.run(sec.P, {})), sec.P) + 1e-3
      -- a reachable tol: the report says the truth, whichever way the search ended
      -- (periodic always meets it here: it may interpolate)
      local C2, rep2 = st.run(sec.P, { tol = loose })
      local within = max_distance(C2, sec.P) <= loose * (1 + 1e-9)
      T.eq(rep2.tol_met, within, s .. " " .. sec.name)
      T.eq(#rep2.warnings, within and 0 or 1, s .. " " .. sec.name)
      if s == "periodic" then T.ok(within, sec.name) end
    end
  end
end)
