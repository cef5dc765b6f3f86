-- lua/bsfit/svg_surface.lua
-- A preview of a skinned surface (the scan pipeline's surface.svg; docs/pictures.md): a
-- wireframe of iso-parameter lines in an oblique parallel projection, the parts facing
-- away from the viewer lighter and dashed, and the fitted section curves drawn on it. In
-- data units like the other pictures: a parallel projection keeps lengths parallel to the
-- screen, so the scale bar holds; a triad shows where x, y and z point.
--
--   local svg_surface = require "bsfit.svg_surface"
--   local text = svg_surface.picture { surface = S, sections = {C1, ...}, up = {0, 0, 1} }
--
-- Hidden parts are told by the normal: a point whose outward normal faces away from the
-- viewer is behind the surface (exact for the convex parts; a preview elsewhere).
-- Every iso-line is one <path class="iso"> (its visible runs as subpaths) and, where some
-- of it is hidden, one <path class="iso-hidden">; each section one <path class="section">
-- (and "section-hidden").

local plot = require "bsfit.plot"
local svg = require "bsfit.svg"

local M = {}

M.U_LINES = 24   -- iso-u lines (along the surface, across the sections)
M.V_LINES = 12   -- iso-v lines (around)
M.SAMPLES = 160  -- points per iso-line

local function dot(a, b) return a[1] * b[1] + a[2] * b[2] + a[3] * b[3] end
local function cross(a, b)
  return { a[2] * b[3] - a[3] * b[2], a[3] * b[1] - a[1] * b[3], a[1] * b[2] - a[2] * b[1] }
end
local function unit(a)
  local n = math.sqrt(dot(a, a))
  return { a[1] / n, a[2] / n, a[3] / n }
end

-- The view: screen axes e1 (right), e2 (up) and w (towards the viewer), for the object's
-- axis `up` seen from azimuth az and elevation el (degrees) about it.
function M.view(up, az, el)
  local a = unit(up)
  local h = math.abs(a[3]) < 0.9 and { 0, 0, 1 } or { 1, 0, 0 }
  local h1 = unit(cross(h, a))
  if math.abs(a[3]) >= 0.9 then h1 = { a[3] > 0 and 1 or -1, 0, 0 } end
  local h2 = cross(a, h1)
  local ca, sa, ce, se = math.cos(math.rad(az)), math.sin(math.rad(az)),
    math.cos(math.rad(el)), math.sin(math.rad(el))
  local w, e1 = {}, {}
  for t = 1, 3 do
    w[t] = ce * (ca * h1[t] + sa * h2[t]) + se * a[t]
    e1[t] = -sa * h1[t] + ca * h2[t]
  end
  return { e1 = e1, e2 = cross(w, e1), w = w }
end

-- {======================================================================
-- Lines and their visibility
-- =======================================================================

-- Points of S along a line: (u, v) = at(i / n) for i = 0..n; each {x, y, front} with x, y
-- on the screen; front: the normal (oriented by sign) faces the viewer (nil normal: front).
local function trace(S, V, at, n, sign)
  local pts = {}
  for i = 0, n do
    local u, v = at(i / n)
    local P = { S:eval(u, v) }
    local N = { S:normal(u, v) }
    local front = N[1] == nil or sign * dot(N, V.w) >= 0
    pts[i + 1] = { dot(P, V.e1), dot(P, V.e2), front }
  end
  return pts
end

-- +1 when S:normal points outwards (away from the centre of its own v-row), else -1.
local function orientation(S)
  local score = 0
  for j = 1, 5 do
    local v, row, c = (j - 0.5) / 5, {}, { 0, 0, 0 }
    for i = 1, 16 do
      row[i] = { S:eval((i - 1) / 16, v) }
      for t = 1, 3 do c[t] = c[t] + row[i][t] / 16 end
    end
    for i = 1, 16 do
      local N = { S:normal((i - 1) / 16, v) }
      if N[1] then
        score = score + dot(N, { row[i][1] - c[1], row[i][2] - c[2], row[i][3] - c[3] })
      end
    end
  end
  return score >= 0 and 1 or -1
end

-- The path data of a line's runs of one kind (front or hidden): "M x y L x y ..." per run;
-- a run includes the point where it turns, so runs meet.
local function runs(f, pts, want)
  local d, open = {}, false
  for i, q in ipairs(pts) do
    local take = q[3] == want or (pts[i - 1] and pts[i - 1][3] == want)
    if take then
      d[#d + 1] = (open and "L" or "M") .. f:x(q[1]) .. " " .. f:y(q[2])
      open = true
    else
      open = false
    end
  end
  return table.concat(d, " ")
end

-- }======================================================================

-- The lines: iso-u, iso-v and sections, each {pts, kind}, and the box of every point.
local function lines(o, V)
  local S, n, sign = o.surface, o.samples or M.SAMPLES, orientation(o.surface)
  local ua, ub, va, vb = S:domain()
  local out = {}
  for i = 0, (o.u_lines or M.U_LINES) - 1 do
    local u = ua + (ub - ua) * i / (o.u_lines or M.U_LINES)
    out[#out + 1] = { kind = "iso", pts = trace(S, V, function(s) return u, va + (vb - va) * s end, n, sign) }
  end
  for j = 0, (o.v_lines or M.V_LINES) - 1 do
    local v = va + (vb - va) * j / ((o.v_lines or M.V_LINES) - 1)
    out[#out + 1] = { kind = "iso", pts = trace(S, V, function(s) return ua + (ub - ua) * s, v end, n, sign) }
  end
  for k, C in ipairs(o.sections or {}) do -- the section near S(., v_k): visibility from there
    local a, b = C:domain()
    local rep = o.report
    local pts = trace(S, V, function(s) return ua + (ub - ua) * s, rep.v_params[k] end, n, sign)
    for i = 0, n do
      local u = i / n
      local t = rep.reversed[k] and rep.shifts[k] - (b - a) * u or rep.shifts[k] + (b - a) * u
      local P = { C:eval(a + (t - a) % (b - a)) }
      pts[i + 1][1], pts[i + 1][2] = dot(P, V.e1), dot(P, V.e2)
    end
    out[#out + 1] = { kind = "section", pts = pts }
  end
  local x0, y0, x1, y1 = math.huge, math.huge, -math.huge, -math.huge
  for _, l in ipairs(out) do
    for _, q in ipairs(l.pts) do
      x0, y0 = math.min(x0, q[1]), math.min(y0, q[2])
      x1, y1 = math.max(x1, q[1]), math.max(y1, q[2])
    end
  end
  local pad = 0.04 * math.max(x1 - x0, y1 - y0, 1e-300)
  return out, { x0 - pad, y0 - pad, x1 + pad, y1 + pad }
end

local STYLE = {
  iso = 'stroke="#2b5c8a" stroke-width="%s"',
  ["iso-hidden"] = 'stroke="#9fb6cc" stroke-width="%s" stroke-dasharray="%s"',
  section = 'stroke="#d62728" stroke-width="%s"',
  ["section-hidden"] = 'stroke="#eb9394" stroke-width="%s" stroke-dasharray="%s"',
}

local function style(f, class)
  local w = class:find("section") and 2 or 1
  return STYLE[class]:format(f:c(f:px(w)), f:c(f:px(4)))
end

-- The triad: x, y, z as seen, from a corner of the plot.
local function triad(f, V, out)
  local len, cx, cy = f:px(26), f.x1 - f:px(40), f.y0 + f:px(40)
  out[#out + 1] = ('<g class="triad" stroke="#333" stroke-width="%s" font-size="%s">')
    :format(f:c(f:px(1.2)), f:c(f:px(plot.SMALL)))
  for t, name in ipairs { "x", "y", "z" } do
    local e = { 0, 0, 0 }
    e[t] = 1
    local x, y = cx + len * dot(e, V.e1), cy + len * dot(e, V.e2)
    out[#out + 1] = ('<line x1="%s" y1="%s" x2="%s" y2="%s"/>')
      :format(f:X(cx), f:Y(cy), f:X(x), f:Y(y))
    out[#out + 1] = f:text(x + f:px(3), y - f:px(4), name, plot.SMALL, "middle", 'stroke="none"')
  end
  out[#out + 1] = "</g>"
end

local function legend(f, out)
  local x, y = f.x1 + f:px(18), f.y1 - f:px(4)
  out[#out + 1] = '<g class="legend" fill="#222">'
  for _, e in ipairs { { "iso", "iso-parameter lines" }, { "iso-hidden", "hidden (facing away)" },
                       { "section", "fitted sections" }, { "section-hidden", "hidden sections" } } do
    y = y - f:px(20)
    out[#out + 1] = ('<line x1="%s" y1="%s" x2="%s" y2="%s" %s/>')
      :format(f:X(x), f:Y(y), f:X(x + f:px(22)), f:Y(y), style(f, e[1]))
    out[#out + 1] = f:text(x + f:px(28), y - f:px(plot.FONT / 3), e[2], plot.FONT)
  end
  out[#out + 1] = "</g>"
end

-- The SVG text. o: surface (required), sections (3D curves) with report (bs.surface.skin's:
-- v_params, shifts, reversed), up (the object's axis, default {0, 0, 1}), azimuth (-35) and
-- elevation (25) in degrees, u_lines, v_lines, samples, size (640), title, subtitle.
function M.picture(o)
  local az, el = o.azimuth or -35, o.elevation or 25
  local V = M.view(o.up or { 0, 0, 1 }, az, el)
  local L, box = lines(o, V)
  local f = plot.frame { box = box, size = o.size or 640, left = 16, right = 210, top = 70,
                         bottom = 3 * plot.SMALL + 40, min_height = 200 }
  local out = { f:open(), f:background(),
    '<g class="data" transform="scale(1,-1)" fill="none" stroke-linejoin="round">' }
  for _, pass in ipairs { false, true } do -- hidden parts first, under the visible ones
    for _, line in ipairs(L) do
      local class = line.kind .. (pass and "" or "-hidden")
      local d = runs(f, line.pts, pass)
      if d ~= "" or (pass and line.kind == "iso") then
        out[#out + 1] = ('<path class="%s" d="%s" %s/>'):format(class, d, style(f, class))
      end
    end
  end
  out[#out + 1] = "</g>"
  triad(f, V, out)
  svg.scale_bar(f, out)
  local l, _, _, t = f:view()
  local x, y = l + f:px(8), t - f:px(24)
  out[#out + 1] = f:text(x, y, o.title or "surface", 16, "start", 'font-weight="bold"')
  out[#out + 1] = f:text(x, y - f:px(16), o.subtitle or ("oblique parallel view: azimuth %g°, "
    .. "elevation %g°; hidden parts dashed"):format(az, el), plot.SMALL, "start",
    'class="note" fill="#444"')
  legend(f, out)
  out[#out + 1] = "</svg>\n"
  return table.concat(out, "\n")
end

return M
