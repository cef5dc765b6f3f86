-- test_carvalho_bound.lua: carvalho's start-point search refits at most `candidates`
-- (16) points by default, those of largest angle; "all" is the paper's literal search.
-- The work is counted (calls of the fit step), not timed.
local T = require "tap"
local bs = require "bsfit"
local synth = require "synth"
local carvalho = require "bsfit.strategy.carvalho"

local function counting_fit()
  local calls = 0
  return function(P, ctx) calls = calls + 1; return carvalho.steps.fit(P, ctx) end,
         function() return calls end
end

T.test("default: at most 16 refits, the candidates of largest angle", function()
  for _, m in ipairs { 200, 800, 2000 } do
    for name, f in pairs(synth.smooth) do
      local P = synth.noisy(synth.sample_smooth(f, m, true), 0.002, m)
      local fit, calls = counting_fit()
      local C, rep = carvalho.run(P, { fit = fit })
      T.ok(C, name)
      T.ok(rep.candidates_tried <= 16 and rep.candidates_tried == #rep.candidates, name)
      T.ok(rep.candidates_found >= rep.candidates_tried, name)
      T.ok(calls() <= 1 + rep.candidates_tried, ("%s m=%d: %d fits"):format(name, m, calls()))
      -- the kept candidates are the largest angles among those that qualified
      local a = bs.geom.angles(P, { closed = true }):totable()
      local mean, sd = 0, 0
      for i = 1, #a do mean = mean + a[i] end
      mean = mean / #a
      for i = 1, #a do sd = sd + (a[i] - mean) ^ 2 end
      sd = math.sqrt(sd / #a)
      local kept, smallest_kept = {}, math.huge
      for _, i in ipairs(rep.candidates) do
        kept[i] = true
        smallest_kept = math.min(smallest_kept, a[i])
      end
      for i = 1, #a do
        if not kept[i] and a[i] > mean + sd / 2 then T.ok(a[i] <= smallest_kept, name) end
      end
    end
  end
end)

T.test("candidates = 'all' refits every qualifying point; a number bounds it", function()
  local P = synth.noisy(synth.sample_smooth(synth.smooth.star, 300, true), 0.002, 5)
  local fit, calls = counting_fit()
  local C, rep = carvalho.run(P, { fit = fit, candidates = "all" })
  T.ok(C)
  T.eq(rep.candidates_tried, rep.candidates_found)
  T.ok(rep.candidates_found > 16)
  T.ok(calls() >= rep.candidates_found)
  local _, rep1 = carvalho.run(P, { candidates = 1 })
  T.eq(rep1.candidates_tried, 1)
  -- the full search can only find a start at least as good (smallest dt_1 + dt_2)
  local best_all, best16 = math.huge, math.huge
  for _, d in ipairs(rep.candidate_dt) do best_all = math.min(best_all, d) end
  local _, rep16 = carvalho.run(P, {})
  for _, d in ipairs(rep16.candidate_dt) do best16 = math.min(best16, d) end
  T.ok(best_all <= best16)
  for _, bad in ipairs { 0, -1, 1.5, "some" } do
    T.raises("bad argument #2 to 'run' (option 'candidates' must be an integer >= 1 or \"all\")",
             function() carvalho.run(P, { candidates = bad }) end)
  end
end)
