-- test_auto.lua: bsfit.strategy.auto against sections with known truth and known noise
-- (tests/lua/synth.lua): Hausdorff distance to the truth compared with the paper's
-- strategy, corners, outliers, self-intersection, total turning, the noise estimate,
-- and the kernels behind it (bs.params_trusted, bs.knots.breaks).
local T = require "tap"
local bs = require "bsfit"
local synth = require "synth"
local auto = require "bsfit.strategy.auto"
local carvalho = require "bsfit.strategy.carvalho"

local TWO_PI = 2 * math.pi

-- total turning of the dense closed truth polyline
local function polyline_turning(pts)
  local n, total = #pts, 0
  for i = 1, n do
    local a, b, c = pts[(i - 2) % n + 1], pts[i], pts[i % n + 1]
    local t1 = math.atan(b[2] - a[2], b[1] - a[1])
    local t2 = math.atan(c[2] - b[2], c[1] - b[1])
    local d = (t2 - t1 + math.pi) % TWO_PI - math.pi
    total = total + math.abs(d)
  end
  return total
end

T.test("noise estimate within 20% on smooth shapes, even and uneven spacing", function()
  for name, f in pairs(synth.smooth) do
    for _, sigma in ipairs { 1e-4, 1e-3, 1e-2 } do
      for _, uneven in ipairs { false, true } do
        local P = synth.noisy(synth.sample_smooth(f, 1500, uneven), sigma, 11)
        local est = bs.geom.noise_sigma(P)
        T.ok(math.abs(est - sigma) <= 0.2 * sigma,
             ("%s sigma %g uneven %s: estimate %g"):format(name, sigma, tostring(uneven), est))
      end
    end
  end
end)

T.test("auto beats carvalho on noisy smooth shapes and is never >10% worse on clean ones", function()
  for name, f in pairs(synth.smooth) do
    local truth = synth.sample_smooth(f, 800, false)
    local turning = polyline_turning(truth)
    for _, sigma in ipairs { 0, 1e-3, 1e-2 } do
      for _, uneven in ipairs { false, true } do
        local P = synth.noisy(synth.sample_smooth(f, 200, uneven), sigma, 7)
        local Ca, rep = auto.run(P)
        local Cc = carvalho.run(P)
        local ha, hc = synth.hausdorff(Ca, truth), synth.hausdorff(Cc, truth)
        local what = ("%s sigma %g uneven %s: auto %g carvalho %g"):format(name, sigma, tostring(uneven), ha, hc)
        if sigma > 0 then T.ok(ha < hc, what) else T.ok(ha <= 1.1 * hc, what) end
        T.eq(#rep.corners, 0, what .. ": false corners")
        T.ok(not synth.self_intersects(Ca), what .. ": self-intersection")
        local tt = Ca:total_turning()
        T.ok(math.abs(tt - turning) <= 0.1 * turning, ("%s: turning %g, truth %g"):format(what, tt, turning))
      end
    end
  end
end)

T.test("a noisy section of 10^4 points gets a count set by its shape, not its size", function()
  local P = synth.noisy(synth.sample_smooth(synth.smooth.star, 10000, true), 1e-3, 5)
  local C, rep = auto.run(P)
  T.ok(rep.count <= 120, "count " .. rep.count)
  T.ok(synth.hausdorff(C, synth.sample_smooth(synth.smooth.star, 800, false)) < 3e-3)
end)

local polygons = {
  square = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } },
  L = { { 0, 0 }, { 1, 0 }, { 1, 0.3 }, { 0.3, 0.3 }, { 0.3, 1 }, { 0, 1 } },
}

T.test("corners: square and L (vertices on and between samples), D shape, airfoil", function()
  local cases = {}
  for name, v in pairs(polygons) do
    cases[#cases + 1] = { name = name, size = 1, corners = #v, truth = v,
                          make = function(m) return synth.sample_polygon(v, m) end }
  end
  cases[#cases + 1] = { name = "D", size = 2, corners = 2, make = synth.d_shape }
  cases[#cases + 1] = { name = "airfoil", size = 1, corners = 1, make = synth.airfoil }
  for _, c in ipairs(cases) do
    local truth = c.truth or c.make(1000)
    for _, sigma in ipairs { 0, 1e-4, 1e-3 } do
      for _, m in ipairs { 150, 400 } do
        local P = synth.noisy(c.make(m), sigma * c.size, 3)
        local C, rep = auto.run(P)
        local h = synth.hausdorff(C, truth, 800)
        local lim = 3 * sigma * c.size + 1e-3 * c.size
        local what = ("%s m %d sigma %g"):format(c.name, m, sigma)
        T.eq(#rep.corners, c.corners, what .. ": corners")
        T.ok(h < lim, ("%s: Hausdorff %g >= %g"):format(what, h, lim))
        -- the airfoil's trailing edge is thinner than the noise near its tip, where the two
        -- sides may cross: only the noise-free airfoil is held to this
        if c.name ~= "airfoil" or sigma == 0 then
          T.ok(not synth.self_intersects(C, 600), what .. ": self-intersection")
        end
      end
    end
  end
end)

-- Seeds as the accuracy sweep drew them (7919 seed + m): each case below failed on at
-- least one of its seeds before the corners and parameters were made noise-aware.
local function sweep_noise(pts, sigma, seed, m) return synth.noisy(pts, sigma, 7919 * seed + m) end

T.test("corners with few samples per side or a curved side: found, Hausdorff < 3 sigma + 1e-3", function()
  local cases = {
    -- the L's short sides hold 11 samples; a D's corner joins a line to an arc
    { name = "L", size = 1, corners = 6, m = 150, sigma = 1e-3, truth = polygons.L,
      make = function(m) return synth.sample_polygon(polygons.L, m) end },
    { name = "square", size = 1, corners = 4, m = 400, sigma = 1e-3, truth = polygons.square,
      make = function(m) return synth.sample_polygon(polygons.square, m) end },
    { name = "D", size = 2, corners = 2, m = 150, sigma = 3e-3, make = synth.d_shape },
    { name = "D", size = 2, corners = 2, m = 400, sigma = 1e-3, make = synth.d_shape },
  }
  for _, c in ipairs(cases) do
    local truth = c.truth or c.make(1000)
    for seed = 1, 3 do
      local P = sweep_noise(c.make(c.m), c.sigma * c.size, seed, c.m)
      local C, rep = auto.run(P)
      local h = synth.hausdorff(C, truth, 800)
      local lim = 3 * c.sigma * c.size + 1e-3 * c.size
      local what = ("%s m %d sigma %g seed %d"):format(c.name, c.m, c.sigma, seed)
      T.eq(#rep.corners, c.corners, what .. ": corners")
      T.ok(h < lim, ("%s: Hausdorff %g >= %g"):format(what, h, lim))
      T.ok(not synth.self_intersects(C, 600), what .. ": self-intersection")
    end
  end
end)

-- Exact spikes with curved (parabolic, not circular) sides: no line or arc explains them,
-- the smooth path keeps the tip as a corner. Its side lines meet beyond the samples, where
-- the tip is; the tip was held back to the furthest sample and the corner placed at it
-- (an exact triangle of 20 samples per side with sides bowed by 1% was 0.27 off at a
-- sample, 0.2% of its size; 0.007 now).
T.test("exact spikes with curved sides: the tip where the sides meet, between samples", function()
  local uniform = synth.rng(4242)
  local n, worst_point, worst_fit = 0, 0, 0
  for k = 1, 24 do
    local apex = math.rad(12 + 40 * uniform()) -- the spike's angle at its tip
    local L, per = 100 * (0.5 + uniform()), 20 + (k % 3) * 10
    local tip, rot = { 0, 0 }, 2 * math.pi * uniform()
    local function at(r, a) return { r * math.cos(rot + a), r * math.sin(rot + a) } end
    local V = { tip, at(L, apex / 2), at(L, -apex / 2) }
    local bows = { 0.003 + 0.007 * uniform(), -0.004, 0.003 + 0.007 * uniform() }
    local pts = {}
    for s = 1, 3 do
      local a, b = V[s], V[s % 3 + 1]
      local dx, dy = b[1] - a[1], b[2] - a[2]
      local len = math.sqrt(dx * dx + dy * dy)
      for j = 0, per - 1 do
        local f = (j + 0.3 + 0.4 * uniform()) / per
        local off = bows[s] * len * 4 * f * (1 - f)
        pts[#pts + 1] = { a[1] + f * dx + off * dy / len, a[2] + f * dy - off * dx / len }
      end
    end
    local P = bs.points.new(pts)
    local idx, _, pos, X = bs.geom.corners(P, { closed = true })
    local what = ("spike %d: apex %.0f deg, %d samples per side"):format(k, math.deg(apex), per)
    local found
    for i = 1, #idx do
      local x, y = X:get(i)
      if math.sqrt(x * x + y * y) < 0.01 * L then found = i end
    end
    T.ok(found, what .. ": the tip is a corner")
    if found then
      local x, y = X:get(found)
      local p = pos:get(found) % #pts -- between the last sample (3 per) and the first
      local off = math.sqrt(x * x + y * y)
      worst_point = math.max(worst_point, off / L)
      T.ok(off <= 5e-3 * L, what .. (": tip %.3g off"):format(off))
      T.ok(p > 3 * per - 1 and p < 3 * per and p ~= math.floor(p) or p > 0 and p < 1,
           what .. (": tip at position %.15g, not between the samples beside it")
             :format(pos:get(found)))
      local _, rep = auto.run(P)
      worst_fit = math.max(worst_fit, rep.max / L)
      T.ok(rep.max <= 1e-3 * L, what .. (": auto %.3g from a sample"):format(rep.max))
      n = n + 1
    end
  end
  print(("# %d spikes, tips within %.3g of a side, fits within %.3g")
    :format(n, worst_point, worst_fit))
end)

T.test("no false corners where smooth bends look like corners (noise 0.3%, sparse uneven samples)", function()
  local f = synth.smooth.star
  for seed = 1, 3 do
    -- noise 0.3% of the size: a valley of radius 0.25 is 40 sigma, the window's scale
    local P = sweep_noise(synth.sample_smooth(f, 400, false), 3e-3 * 2, seed, 400)
    local _, rep = auto.run(P)
    T.eq(#rep.corners, 0, ("star m 400 sigma 3e-3 seed %d: false corners"):format(seed))
    -- 200 uneven samples: a valley turns at a few samples in a row, noise 1e-4
    P = sweep_noise(synth.sample_smooth(f, 200, true), 2e-4, seed, 200)
    _, rep = auto.run(P)
    T.eq(#rep.corners, 0, ("star m 200 uneven sigma 1e-4 seed %d: false corners"):format(seed))
  end
end)

-- Where the sides of a corner meet past the sample after its gap (or short of the one
-- before), the curve forced through that point runs on past the sample and turns back to
-- it: a hook. An exact 5-lobed star of 80 uneven samples (a held-out probe), its noise
-- read from the lobes' curvature, had two false corners of 34 degrees drawn as hooks of
-- 157. bs.geom.corners now refuses such a corner when its point lies more than 3 sigma
-- outside the gap (a spike's tip, which lies beyond its samples, excepted; within the
-- noise a true corner next to a sample can lie past it). Measured here without the
-- detector's own terms: the polygon from the sample before a corner point through it to
-- the sample after turns by far more than the corner's sides (45 degrees more) only at a
-- hook. On 1200 stars of 3 to 8 lobes, 40 to 160 uneven samples, exact or at noise 1e-3
-- and 3e-3 of their size: 78 of 186 such corners were hooks before, 52 of 154 now (HOOKS;
-- the rest lie within 3 sigma of the gap, or have sides curved so that their lines meet
-- inside it while the samples beside it do not).
local HOOKS = 52
T.test("corners between samples: their sides meet inside the gap, not past a sample", function()
  local hooks, between, list = 0, 0, {}
  for _, seed in ipairs { 5, 11 } do
    local uniform, gauss = synth.rng(seed)
    for case = 1, 600 do
      local k, A = 3 + math.floor(6 * uniform()), 0.08 + 0.22 * uniform()
      local phase, m = TWO_PI * uniform(), 40 + math.floor(120 * uniform())
      local warp, psi = 0.35 * uniform(), TWO_PI * uniform()
      local rel = ({ 0, 1e-3, 3e-3 })[case % 3 + 1]
      local pts = {}
      for i = 0, m - 1 do
        local t = TWO_PI * i / m
        t = t + warp * math.sin(2 * t + psi) / 2
        local r = 1 + A * math.cos(k * t + phase)
        pts[#pts + 1] = { r * math.cos(t) + 2 * rel * gauss(), r * math.sin(t) + 2 * rel * gauss() }
      end
      local P = bs.points.new(pts)
      local sigma = bs.geom.noise_sigma(P, { closed = true })
      local _, turns, where, at = bs.geom.corners(P, { closed = true, sigma = sigma > 0 and sigma or nil })
      local W, X, deg = where:totable(), at:totable(), turns:totable()
      for i = 1, #W do
        local j = math.floor(W[i])
        if W[i] > j and deg[i] <= 120 then
          between = between + 1
          local a, b, x = pts[(j - 1) % m + 1], pts[j % m + 1], X[i]
          local ux, uy, vx, vy = a[1] - x[1], a[2] - x[2], b[1] - x[1], b[2] - x[2]
          local c = (ux * vx + uy * vy) / math.sqrt((ux * ux + uy * uy) * (vx * vx + vy * vy))
          local polygon_turn = 180 - math.deg(math.acos(math.max(-1, math.min(1, c))))
          if polygon_turn > deg[i] + 45 then
            hooks = hooks + 1
            list[#list + 1] = ("seed %d case %d: %.0f against %.0f"):format(seed, case, polygon_turn, deg[i])
          end
        end
      end
    end
  end
  T.ok(hooks <= HOOKS, ("%d of %d corners between samples hook (at most %d): %s"):format(hooks, between,
    HOOKS, table.concat(list, "; ", 1, math.min(#list, 6))))
end)

-- A smooth noisy shape is followed by tangent arcs and lines within the noise (a cam by
-- four arcs, an ellipse by an oval of four), but its curvature changes along them: such
-- pieces were taken for 18 of the 180 sections below, 3 to 7 times farther from the truth
-- than the smooth curve. Pieces without a corner must explain the samples as well as the windows.
-- Three remain (an ellipse of 80 or 200 samples at noise 3e-3, 0.0075 of its size of 2,
-- is within that noise of a four-arc oval: the pieces' residual is below the windows').
T.test("a smooth noisy shape is not read as tangent lines and arcs", function()
  local shapes, names = synth.smooth_shapes()
  local tangent_only, total = {}, 0
  for seed = 1, 3 do
    for _, name in ipairs(names) do
      for _, m in ipairs { 40, 80, 200 } do
        for j, rel in ipairs { 1e-3, 3e-3 } do
          for _, uneven in ipairs { false, true } do
            local P = synth.noisy(synth.sample_smooth(shapes[name], m, uneven), 2.5 * rel, 1000 * seed + m + j + 1)
            local _, rep = auto.run(P)
            total = total + 1
            if rep.pieces and #rep.corners == 0 then
              tangent_only[#tangent_only + 1] = ("%s m %d noise %g%s seed %d"):format(name, m, rel,
                uneven and " uneven" or "", seed)
            end
          end
        end
      end
    end
  end
  T.ok(#tangent_only <= 3, ("%d of %d smooth sections as tangent pieces: %s"):format(#tangent_only, total,
    table.concat(tangent_only, ", ")))
end)

T.test("dense clusters of samples neither loop nor make corners", function()
  local f = synth.smooth.ellipse
  local truth = synth.sample_smooth(f, 800, false)
  for _, sigma in ipairs { 1e-4, 3e-3 } do
    for seed = 1, 2 do
      -- 600 samples and 4 bursts of 100 nearly coincident ones
      local P = sweep_noise(synth.clustered(f, 1000, 4, 0.1), 2 * sigma, seed, 1000)
      local C, rep = auto.run(P)
      local what = ("clustered sigma %g seed %d"):format(sigma, seed)
      T.eq(#rep.corners, 0, what .. ": corners")
      T.ok(not synth.self_intersects(C, 600), what .. ": self-intersection")
      local h, lim = synth.hausdorff(C, truth), 3 * 2 * sigma + 2e-3
      T.ok(h < lim, ("%s: Hausdorff %g >= %g"):format(what, h, lim))
    end
  end
end)

T.test("an airfoil's thin trailing edge does not cross over; noise a few percent low does not overfit", function()
  local truth = synth.airfoil(1000)
  for seed = 1, 3 do
    -- noise 1e-3 of the chord: the last 0.3% of the edge is thinner than the noise
    local P = sweep_noise(synth.airfoil(400), 1e-3, seed, 400)
    local C, rep = auto.run(P)
    local what = ("airfoil m 400 sigma 1e-3 seed %d"):format(seed)
    T.eq(#rep.corners, 1, what .. ": corners")
    T.ok(not synth.self_intersects(C, 600), what .. ": self-intersection")
    T.ok(synth.hausdorff(C, truth, 800) < 4e-3, what .. ": Hausdorff")
    -- noise 1e-4: the count search stops where more control points buy no more than
    -- fitting noise does, instead of running to its cap
    P = sweep_noise(synth.airfoil(400), 1e-4, seed, 400)
    C, rep = auto.run(P)
    what = ("airfoil m 400 sigma 1e-4 seed %d"):format(seed)
    T.ok(rep.count <= 100, what .. ": count " .. rep.count)
    local h = synth.hausdorff(C, truth, 800)
    T.ok(h < 1.3e-3, ("%s: Hausdorff %g"):format(what, h))
  end
end)

T.test("down-weighted gross outliers are ignored (fit and parameters)", function()
  local f = synth.smooth.ellipse
  local truth = synth.sample_smooth(f, 800, false)
  local pts = synth.sample_smooth(f, 240, false)
  local w = {}
  for i = 1, #pts do w[i] = 1 end
  for _, k in ipairs { 20, 75, 130, 200 } do
    pts[k] = { pts[k][1] * 1.6, pts[k][2] * 1.6 } -- far outside
    w[k] = 1e-3
  end
  local P = synth.noisy(pts, 1e-3, 9)
  local C, rep = auto.run(P, { point_weights = bs.vector.new(w) })
  local h = synth.hausdorff(C, truth)
  T.ok(h < 4e-3, "Hausdorff to the truth " .. h)
  -- the paper's circumradius weights cannot do this
  local Cc = carvalho.run(P, { point_weights = bs.vector.new(w) })
  T.ok(synth.hausdorff(Cc, truth) > h, "carvalho should not beat auto here")
  T.ok(rep.sigma > 0 and rep.sigma < 3e-3, "sigma " .. rep.sigma)
  -- the report separates the trusted points: their distances stay at the noise level
  -- while the outliers' (0.6 of the radius away) dominate the plain maximum
  T.ok(rep.max_trusted and rep.max_trusted < 6e-3, "max over trusted " .. tostring(rep.max_trusted))
  T.ok(rep.max > 0.3, "max over all points " .. rep.max)
  T.ok(rep.rms_trusted < rep.rms, "rms over trusted below rms")
  -- the trusted measure is the residuals' own over the points of weight 1, for auto and
  -- for carvalho (common.measure_of, summed in C)
  for _, r in ipairs { rep, select(2, carvalho.run(P, { point_weights = bs.vector.new(w) })) } do
    local sum, top, at, n = 0, -1, 0, 0
    for i, d in ipairs(r.residuals) do
      if w[i] == 1 then
        n, sum = n + 1, sum + d * d
        if d > top then top, at = d, i end
      end
    end
    T.near(r.rms_trusted, math.sqrt(sum / n), 1e-12, "rms over trusted")
    T.eq(r.max_trusted, top, "max over trusted")
    T.eq(r.max_trusted_index, at, "index of the max over trusted")
  end
end)

T.test("bad point weights name the value, counted from 1", function()
  local P = bs.points.new(synth.sample_smooth(synth.smooth.ellipse, 50, false))
  for _, bad in ipairs { -2, 0, 0 / 0, math.huge, "x" } do
    local w = {}
    for i = 1, #P do w[i] = 1 end
    w[7] = bad
    local ok, err = pcall(auto.run, P, { point_weights = w })
    T.ok(not ok and err:match("^point_weights: value 7 is .* %(must be positive and finite%)$"),
         "weight " .. tostring(bad) .. ": " .. tostring(err))
  end
end)

T.test("every step can be switched off or replaced", function()
  local P = synth.noisy(synth.sample_polygon(polygons.square, 200), 1e-3, 2)
  local _, r1 = auto.run(P, { corners = {} })
  T.eq(#r1.corners, 0)
  local _, r2 = auto.run(P, { count = 30 })
  T.eq(r2.count, 30)
  local _, r3 = auto.run(P, { correct = 0 })
  T.ok(r3.rms > 0 and r3.rms < 5e-3, "fit without parameter correction: rms " .. r3.rms)
  local _, r4 = auto.run(P, { tol = 5e-3 })
  T.ok(r4.max <= 5e-3, "tol met: " .. r4.max)
  T.raises({ match = "unknown option 'bogus'" }, function() auto.run(P, { bogus = 1 }) end)
end)

T.test("robust = true: Huber reweighting lets the curve move away from a gross outlier", function()
  local pts = synth.sample_smooth(synth.smooth.circle, 200, false)
  pts[50] = { pts[50][1] * 1.15, pts[50][2] * 1.15 } -- 0.15 out, full weight
  local P = synth.noisy(pts, 1e-3, 12)
  local _, plain = auto.run(P)
  local _, robust = auto.run(P, { robust = true })
  -- the outlier's own distance grows: the curve is pulled toward it less
  T.ok(robust.residuals[50] > plain.residuals[50] + 1e-3,
       ("outlier distance %g (robust) vs %g (plain)"):format(robust.residuals[50], plain.residuals[50]))
  T.ok(robust.residuals[50] > 0.1, "the robust curve stays near the circle: " .. robust.residuals[50])
end)

T.test("trusted parameters: an outlier does not stretch its neighbours", function()
  local pts = synth.sample_smooth(synth.smooth.circle, 60, false)
  local clean = {}
  for i, p in ipairs(pts) do if i ~= 10 then clean[#clean + 1] = p end end
  pts[10] = { 3, 3 }
  local w = {}
  for i = 1, 60 do w[i] = i == 10 and 1e-4 or 1 end
  local u = bs.params_trusted(bs.points.new(pts), "chord", { weights = w })
  local uc = bs.params(bs.points.new(clean), "chord", { closed = true })
  local j = 0
  for i = 1, 60 do
    if i ~= 10 then j = j + 1; T.near(u:get(i), uc:get(j), 1e-12) end
  end
  T.near(u:get(10), 0.5 * (u:get(9) + u:get(11)), 1e-12)
  T.raises({ match = "trust" }, function() bs.params_trusted(bs.points.new(pts), "chord", { trust = 2 }) end)
end)

T.test("knots with corner breaks: multiplicity 3 at the corners, no empty span", function()
  local P = bs.points.new(synth.sample_polygon(polygons.square, 200))
  local u = bs.params(P, "chord", { closed = true })
  local K, N = bs.knots.breaks { params = u, degree = 3, count = 20, breaks = { 1, 51, 101, 151 } }
  T.eq(N, 20)
  T.eq(#K, 21)
  local t = K:totable()
  local mult = {}
  for i = 1, N do mult[t[i]] = (mult[t[i]] or 0) + 1 end
  for _, k in ipairs { 1, 51, 101, 151 } do T.eq(mult[u:get(k)], 3, "corner knot " .. k) end
  T.near(t[N + 1] - t[1], 1, 1e-15)
  T.raises({ match = "breaks" }, function() bs.knots.breaks { params = u, count = 20, breaks = { 5, 3 } } end)
end)

-- Sparse noisy open runs (spirals, sines, arcs of 200 to 340 degrees; 8 to 32 samples;
-- noise 3e-4 to 3e-2 of their scale): a curve every time, auto, open, or with a count of
-- 6 asked for. A spiral of 21 samples whose windows read its curvature as noise had its
-- anchors (4 sigma apart) too few for the fewest control points, and the knot placement
-- raised an internal error ("5 parameters are fewer than 8 control points"); the knots now
-- go on the samples there, whatever the count.
T.test("sparse noisy open runs: a curve, never an internal error", function()
  local uniform, gauss = synth.rng(2024)
  for k = 1, 600 do
    local m, kind = 8 + math.floor(25 * uniform()), k % 3
    local sigma, turns = 10 ^ (-3.5 + 2 * uniform()), 1 + 1.5 * uniform()
    local pts = {}
    for j = 1, m do
      local f, x, y = (j - 1) / (m - 1), 0, 0
      if kind == 0 then
        local t, r = TWO_PI * turns * f, 1 + 4 * f
        x, y = r * math.cos(t), r * math.sin(t)
      elseif kind == 1 then
        x, y = 10 * f, math.sin(TWO_PI * turns * f)
      else
        local t = math.rad(200 + 140 * uniform()) * f
        x, y = 5 * math.cos(t), 5 * math.sin(t)
      end
      pts[j] = { x + 5 * sigma * gauss(), y + 5 * sigma * gauss() }
    end
    for _, o in ipairs { {}, { closed = false }, { count = 6 } } do
      local ok, C, rep = pcall(auto.run, bs.points.new(pts), o)
      local what = ("run %d (kind %d, %d samples, noise %.2g, %s)"):format(k, kind, m, sigma,
        o.count and "count 6" or o.closed == false and "open" or "auto")
      T.ok(ok, what .. ": " .. tostring(C))
      T.ok(rep.max < math.huge and C:distinct() >= 4, what .. ": a finite curve")
    end
  end
end)
