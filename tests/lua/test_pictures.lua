-- test_pictures.lua: bsfit.svg's section picture and bsfit.overview's page, checked
-- against the data they draw (computed here independently): the viewBox holds every
-- point in data units with y up (less a round origin, in a power-of-ten unit, when the
-- data are far from 0 or of extreme size), text is laid out in pixels, the worst
-- residual's label lies inside the view box,
-- down-weighted points (the strategies' rule: weight < 0.1 x median) are the hollow
-- ones, colours follow the residuals, a 3D section's plane drawing keeps distances,
-- and a huge section gives a bounded picture.
local T = require "tap"
local bs = require "bsfit"
local svg = require "bsfit.svg"
local plot = require "bsfit.plot"
local overview = require "bsfit.overview"

-- A pseudo-random generator of our own (deterministic across Lua builds).
local function rng(seed)
  local s = seed
  return function()
    s = (s * 1103515245 + 12345) % 2147483648
    return s / 2147483648
  end
end

-- A closed wobbly section: m points, radius r around (cx, cy), noise amplitude a.
local function section(m, r, cx, cy, a, rand)
  local t, res = {}, {}
  local k = 2 + math.floor(rand() * 5)
  for i = 1, m do
    local th = 2 * math.pi * (i - 1) / m
    local e = a * (rand() - 0.5)
    local rr = r * (1 + 0.2 * math.cos(k * th)) + e
    t[i] = { cx + rr * math.cos(th), cy + rr * math.sin(th) }
    res[i] = math.abs(e)
  end
  return bs.points.new(t), res
end

local function numbers(s)
  local t = {}
  for v in s:gmatch("[-%d.e+]+") do t[#t + 1] = tonumber(v) end
  return t
end

-- A picture's map from the numbers written to data coordinates: x = ox + unit * v
-- (svg attributes data-origin, data-unit), y = oy + unit * v in the flipped data group
-- and oy - unit * v outside it.
local function picture_map(text)
  local o = numbers(text:match('data%-origin="([^"]*)"'))
  local unit = tonumber(text:match('data%-unit="([^"]*)"'))
  return { ox = o[1], oy = o[2], unit = unit,
           x = function(v) return o[1] + unit * v end,
           y = function(v) return o[2] + unit * v end,
           Y = function(v) return o[2] - unit * v end }
end

-- viewBox as (left, bottom, right, top) in data coordinates (y up).
local function view(text)
  local v, map = numbers(text:match('viewBox="([^"]*)"')), picture_map(text)
  return map.x(v[1]), map.Y(v[2] + v[4]), map.x(v[1] + v[3]), map.Y(v[2])
end

-- Each text element: its data position, font size in data units and in the layout.
local function texts_of(text)
  local t, map = {}, picture_map(text)
  for a, b, k, fs, rest in text:gmatch('<text transform="translate%(([^,]*),([^)]*)%) scale%(([^)]*)%)" '
                                       .. 'font%-size="([^"]*)"([^>]*)>') do
    t[#t + 1] = { x = map.x(tonumber(a)), y = map.Y(tonumber(b)), layout = tonumber(fs),
                  size = tonumber(fs) * tonumber(k) * map.unit, attrs = rest }
  end
  return t
end

T.test("viewBox in data units holds every point; y up; legend, colour bar, max label inside", function()
  local rand = rng(7)
  for trial = 1, 24 do
    local m = 20 + math.floor(rand() * 400)
    local r = 10 ^ (rand() * 14 - 6) -- sizes from 1e-6 to 1e8
    -- centres near 0 and, every other trial, up to 1e7 sizes away (survey coordinates)
    local far = trial % 2 == 0 and 10 ^ (rand() * 7) or 1
    local cx, cy = (rand() - 0.5) * 1e3 * r * far, (rand() - 0.5) * 10 * r * far
    local P, res = section(m, r, cx, cy, 0.05 * r * rand(), rand)
    local imax = 1
    for i = 2, m do if res[i] > res[imax] then imax = i end end
    local text = svg.section { points = P, samples = P, residuals = res, max_index = imax,
                               max = res[imax], closed = true, title = "s" .. trial }
    local l, b, rr, t = view(text)
    local map = picture_map(text)
    local drawn = {}
    for x, y in text:gmatch('<circle cx="([^"]*)" cy="([^"]*)" r="[^"]*" fill="#') do
      drawn[#drawn + 1] = { tonumber(x), tonumber(y) }
    end
    T.ok(#drawn >= m, ("trial %d: %d points drawn"):format(trial, #drawn))
    local vb = numbers(text:match('viewBox="([^"]*)"'))
    local span = math.max(vb[3], vb[4])
    -- renderers draw in single precision and librsvg nothing in a tiny view box: the
    -- numbers written are of the picture's size, whatever the data's offset and scale
    T.ok(span >= 0.01 and span <= 1e7, ("trial %d: view box %g wide"):format(trial, span))
    for i = 1, m do
      local x, y = P:get(i)
      T.ok(x > l and x < rr and y > b and y < t, ("trial %d: point %d inside the view box"):format(trial, i))
      local q = drawn[i]
      T.ok(math.abs(q[1]) <= 2000 * span and math.abs(q[2]) <= 2000 * span,
           ("trial %d: point %d written as a number of the picture's size"):format(trial, i))
      T.ok(math.abs(map.x(q[1]) - x) <= 1e-4 * r and math.abs(map.y(q[2]) - y) <= 1e-4 * r,
           ("trial %d: point %d drawn at its coordinates"):format(trial, i))
    end
    T.ok(text:find('transform="scale(1,-1)"', 1, true), "data drawn in a y-up group")
    T.ok(text:find('class="legend"', 1, true) and text:find('class="colorbar"', 1, true))
    T.ok(text:find('url(#viridis)', 1, true), "the colour bar is the viridis gradient")
    -- text is laid out in pixels (a font of 1e-3 units is hinted to garbage), then scaled
    local all = texts_of(text)
    local _, ntext = text:gsub("<text ", "")
    T.eq(#all, ntext, "every text element moved and scaled to its place")
    for _, e in ipairs(all) do
      T.ok(e.layout >= 8 and e.layout <= 20, ("trial %d: text laid out at %g px"):format(trial, e.layout))
    end
    -- the label: its box (estimated text width) inside the view box
    local lx, ly, fs, label
    for _, e in ipairs(all) do
      if e.attrs:find('class="max-label"', 1, true) then lx, ly, fs = e.x, e.y, e.size end
    end
    label = text:match('class="max%-label"[^>]*>([^<]*)<')
    T.ok(label and label:find(plot.num(res[imax]), 1, true), "the label gives the max value")
    local w = #label * 0.62 * fs
    T.ok(lx >= l and lx + w <= rr and ly - 0.3 * fs >= b and ly + fs <= t,
         ("trial %d: max label inside the view box"):format(trial))
    -- the worst point is drawn in the colour bar's top colour
    T.ok(text:find(('cx="%%-?[%%d.]+" cy="%%-?[%%d.]+" r="[^"]*" fill="%s"'):format(plot.viridis(1))),
         "a point has the top colour")
  end
end)

T.test("down-weighted points: hollow, exactly those under 0.1 x median weight", function()
  local rand = rng(11)
  for _ = 1, 10 do
    local m = 30 + math.floor(rand() * 200)
    local P, res = section(m, 5, 0, 0, 0.1, rand)
    local w, sorted = {}, {}
    for i = 1, m do w[i] = rand() < 0.1 and rand() * 0.05 or 0.5 + rand() end
    for i = 1, m do sorted[i] = w[i] end
    table.sort(sorted)
    local cut, expect = 0.1 * sorted[m // 2 + 1], 0
    for i = 1, m do if w[i] < cut then expect = expect + 1 end end
    local text = svg.section { points = P, residuals = res, weights = bs.vector.new(w) }
    local _, n = text:gsub('<circle class="down"', "")
    T.eq(n, expect, "hollow points")
    if expect > 0 then T.ok(text:find("down-weighted", 1, true), "in the legend") end
  end
end)

T.test("3D: drawn in the best-fit plane, distances kept, said so", function()
  local rand = rng(3)
  for _ = 1, 8 do
    -- a circle of radius R in a random plane through a random centre
    local R, m = 1 + 10 * rand(), 64
    local a, b = rand() * math.pi, rand() * 2 * math.pi
    local n = { math.sin(a) * math.cos(b), math.sin(a) * math.sin(b), math.cos(a) }
    local u = math.abs(n[1]) < 0.9 and { 0, -n[3], n[2] } or { -n[3], 0, n[1] }
    local un = math.sqrt(u[1] ^ 2 + u[2] ^ 2 + u[3] ^ 2)
    for k = 1, 3 do u[k] = u[k] / un end
    local v = { n[2] * u[3] - n[3] * u[2], n[3] * u[1] - n[1] * u[3], n[1] * u[2] - n[2] * u[1] }
    local c, t = { rand() * 100, rand() * 100, rand() * 100 }, {}
    for i = 1, m do
      local th = 2 * math.pi * i / m
      t[i] = {}
      for k = 1, 3 do t[i][k] = c[k] + R * (math.cos(th) * u[k] + math.sin(th) * v[k]) end
    end
    local text = svg.section { points = bs.points.new(t) }
    T.ok(text:find("best-fit plane", 1, true), "the picture says so")
    local pts = {}
    for x, y in text:gmatch('<circle cx="([^"]*)" cy="([^"]*)" r="[^"]*" fill') do
      pts[#pts + 1] = { tonumber(x), tonumber(y) }
    end
    local drawn = table.move(pts, 1, #pts - 1, 1, {}) -- the legend's sample point comes last
    T.eq(#drawn, m, "every point drawn")
    local cx, cy, unit = 0, 0, picture_map(text).unit
    for _, p in ipairs(drawn) do cx, cy = cx + p[1] / m, cy + p[2] / m end
    for _, p in ipairs(drawn) do
      T.near(unit * math.sqrt((p[1] - cx) ^ 2 + (p[2] - cy) ^ 2), R, 1e-4 * R + 10 ^ -8,
             "radius kept")
    end
  end
end)

T.test("a huge section: bounded picture, worst residuals drawn, N of M said", function()
  local m = 400000
  local rand = rng(5)
  local P, res = section(m, 100, 0, 0, 1, rand)
  local worst = {}
  for i = 1, 50 do local k = math.floor(rand() * m) + 1; res[k] = 10 + i; worst[#worst + 1] = k end
  local S = bs.points.new { { 0, 0 }, { 1, 1 } }
  local big = {}
  for i = 1, 100000 do big[i] = { math.cos(i / 1e4), math.sin(i / 1e4) } end
  S = bs.points.new(big)
  local text = svg.section { points = P, residuals = res, samples = S, max_index = worst[50], max = 60 }
  T.ok(#text < 1500000, ("%d bytes for %d points"):format(#text, m))
  T.ok(text:find(("of %d points drawn"):format(m), 1, true), "says how many were drawn")
  local _, ncirc = text:gsub("<circle ", "")
  T.ok(ncirc <= svg.MAX_POINTS + 20, ncirc .. " circles")
  local curve = text:match('<polyline points="([^"]*)" fill="none" class="curve"')
  local _, nsamples = curve:gsub(",", "")
  T.ok(nsamples <= svg.MAX_SAMPLES + 1, nsamples .. " curve samples drawn")
  -- the 50 planted worst residuals (11..60) are all drawn, in colours of the top of the scale
  local _, top = text:gsub('fill="' .. plot.viridis(1) .. '"', "")
  T.ok(top >= 1, "the worst residual has the top colour")
  local dec = #text:match('<circle cx="%-?%d+%.(%d+)"')
  for _, k in ipairs(worst) do
    local x, y = P:get(k)
    local at = ('<circle cx="%.' .. dec .. 'f" cy="%.' .. dec .. 'f"'):format(x, y)
    T.ok(text:find(at, 1, true), "planted worst point " .. k .. " drawn")
  end
end)

T.test("control polygon: drawn up to 60 control points, off beyond unless asked", function()
  local P = section(200, 1, 0, 0, 0, rng(1))
  local few, many = {}, {}
  for i = 1, 20 do few[i] = { P:get(i) } end
  for i = 1, 100 do many[i] = { P:get(i) } end
  T.ok(svg.section { points = P, control = few }:find('class="control"', 1, true))
  local s = svg.section { points = P, control = many }
  T.ok(not s:find('class="control"', 1, true) and s:find("polygon not drawn", 1, true))
  T.ok(svg.section { points = P, control = many, polygon = true }:find('class="control"', 1, true))
end)

T.test("corners and pieces: marked, one legend entry per kind", function()
  local P = section(90, 1, 0, 0, 0, rng(2))
  local s = svg.section { points = P, corners = { 1, 31, 61 },
                          pieces = { { kind = "line", first = 1, count = 31 },
                                     { kind = "arc", first = 31, count = 31 },
                                     { kind = "free", first = 61, count = 31 } } }
  local _, nc = s:gsub('class="corner"', "")
  T.eq(nc, 3)
  for _, k in ipairs { "line", "arc", "free" } do
    T.ok(s:find('class="piece%-' .. k .. '"'), k .. " drawn")
    T.ok(s:find(">" .. k .. " piece<", 1, true), k .. " in the legend")
  end
end)

T.test("overview page: sortable table, failed first, links to the pictures", function()
  local rows = { { name = "a", svg = "a.svg", status = "ok", points = 10, control_points = 5, rms = 0.1, max = 0.2 },
                 { name = "b<", status = "error", error = "b.csv: line 3: not a number" },
                 { name = "c", svg = "c.svg", status = "ok", points = 7, control_points = 4, rms = 0.1,
                   max = 0.3, warnings = "few points" } }
  local html = overview.page("t", rows)
  T.ok(html:find("<script>", 1, true) and html:find('addEventListener("click"', 1, true), "inline sort script")
  T.ok(not html:find('src="http', 1, true) and not html:find('<link', 1, true), "no external files")
  local first = html:find("<tbody>", 1, true)
  local pb, pa = html:find("b&lt;", first, true), html:find('href="a.svg"', first, true)
  T.ok(pb and pa and pb < pa, "the failed section first")
  T.ok(html:find('<a href="c.svg"><img src="c.svg"', 1, true), "thumbnail links to the picture")
  T.ok(html:find("few points", 1, true) and html:find("1 with warnings", 1, true))
  for _, h in ipairs { "name", "points", "control points", "RMS", "max", "status" } do
    T.ok(html:find("<th>" .. h .. "</th>", 1, true), h .. " column")
  end
end)

T.test("bs.svg (C layers): 3D data say they are an x-y projection, 2D data do not", function()
  local C3 = bs.curve.new { degree = 1, control_points = { { 0, 0, 0 }, { 1, 1, 5 } } }
  local d = bs.svg.new(C3)
  d:curve(C3)
  T.ok(d:tostring():find("3D data drawn as its x-y projection", 1, true))
  local P3 = bs.points.new { { 0, 0, 1 }, { 1, 2, 3 } }
  T.ok(bs.svg.new(P3):points(P3):tostring():find("x-y projection", 1, true), "points too")
  local C2 = bs.curve.new { degree = 1, control_points = { { 0, 0 }, { 1, 1 } } }
  T.ok(not bs.svg.new(C2):curve(C2):tostring():find("projection", 1, true), "2D: no note")
end)

T.test("curves drawn together: a curve without a label is drawn but not in the legend", function()
  local curves = {}
  for k = 1, 30 do
    local t = {}
    for i = 1, 50 do local a = 2 * math.pi * i / 50; t[i] = { k * math.cos(a), k * math.sin(a) } end
    curves[k] = { samples = bs.points.new(t), closed = true, colour = plot.viridis(k / 30),
                  class = "section", label = k % 10 == 1 and ("loop %d"):format(k) or nil }
  end
  local s = svg.curves { curves = curves, title = "loops" }
  local _, drawn = s:gsub('<polygon[^>]*class="section"', "")
  T.eq(drawn, 30, "every curve drawn closed")
  local _, named = s:gsub(">loop %d+<", "")
  T.eq(named, 3, "the labelled ones in the legend")
  local _, swatches = s:gsub('<line x1="[^"]*" y1="[^"]*" x2="[^"]*" y2="[^"]*" stroke=', "")
  T.eq(swatches, 3, "a swatch each")
end)
