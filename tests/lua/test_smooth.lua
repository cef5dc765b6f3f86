-- test_smooth.lua: the smoothing step of the strategies (opts.smooth) and `bsfit filter`
local T = require "tap"
local bs = require "bsfit"
local synth = require "synth"
local periodic = require "bsfit.strategy.periodic"
local filter_cli = require "bsfit.cli.filter"

local function noisy_circle()
  return synth.noisy(synth.sample_smooth(synth.smooth.circle, 200, false), 0.01, 4)
end

T.test("smooth = {k = 2} lowers turning and bending of a noisy fit, and says by how much", function()
  local P = noisy_circle()
  local C0 = periodic.run(P)
  local C, rep = periodic.run(P, { smooth = { k = 2 } })
  local s = rep.smoothing
  T.eq(C:degree(), C0:degree() + 1)
  T.ok(s.turning[2] < s.turning[1] and s.bending[2] < s.bending[1], "turning and bending drop")
  T.ok(s.turning[2] >= 2 * math.pi - 1e-9, "a closed curve still turns at least once")
  T.near(s.deviation, C0:max_deviation(C), 1e-12)
  T.near(s.turning[1], C0:total_turning(), 1e-12)
  T.ok(rep.times.smooth ~= nil)
end)

T.test("smooth = {delta = d} filters over [t - d, t + d]; bad values raise", function()
  local P = noisy_circle()
  local _, rep = periodic.run(P, { smooth = { delta = 0.01 } })
  T.ok(rep.smoothing.deviation > 0)
  T.raises({ match = "option 'smooth'" }, function() periodic.run(P, { smooth = 0 }) end)
  T.raises({ match = "option 'smooth'" }, function() periodic.run(P, { smooth = "x" }) end)
end)

T.test("bsfit filter: writes the filtered curve and its picture; usage errors exit 2", function()
  local dir = os.tmpname()
  os.remove(dir)
  os.execute("mkdir -p " .. dir)
  local C = periodic.run(noisy_circle())
  local f = assert(io.open(dir .. "/c.json", "w"))
  f:write(C:to_json())
  f:close()
  T.eq(filter_cli.main { dir .. "/c.json", "-k", "2", "-o", dir .. "/f.json" }, 0)
  local F = bs.curve.read(dir .. "/f.json")
  T.eq(F:degree(), C:degree() + 1)
  T.ok(F:total_turning() < C:total_turning())
  T.ok(io.open(dir .. "/f.svg") ~= nil, "picture written")
  T.eq(filter_cli.main { dir .. "/c.json" }, 2)
  T.eq(filter_cli.main { dir .. "/c.json", "-k", "0" }, 2)
  T.eq(filter_cli.main { dir .. "/missing.json", "-k", "2" }, 1)
  os.execute("rm -rf " .. dir)
end)
