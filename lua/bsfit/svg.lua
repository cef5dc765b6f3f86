-- lua/bsfit/svg.lua
-- The picture of one fitted section (docs/pictures.md): an SVG in the data's units
-- (viewBox in data coordinates, y up) with axes, a scale bar, a legend, the points
-- coloured by residual (viridis, with its colour bar), down-weighted points hollow and
-- grey, the curve, the control polygon (light; off by default past 60 control points),
-- the start point, the worst residual marked with its value, the corners and pieces the
-- strategy reports. A 3D section is drawn in its best-fit plane (PCA) and says so.
-- What is drawn is bounded whatever the section's size: at most max_points points (the
-- worst residuals and an even subsample: "N of M points drawn") and max_samples curve
-- samples.
--
--   local svg = require "bsfit.svg"
--   local text = svg.section{points = P, samples = S, control = C:control_points(),
--                            residuals = rep.residuals, max_index = rep.max_index, ...}

local plot = require "bsfit.plot"
local proj = require "bsfit.projection"

local M = {}

M.DENSE_POLYGON = 60  -- more control points than this: no polygon unless asked
M.MAX_POINTS = 5000   -- points drawn at most (the worst fifth of them by residual)
M.MAX_SAMPLES = 2000  -- curve samples drawn at most

-- Per-point values (a Lua array or a Vector) as a Lua array, so the loops over the
-- points index a table (a Vector is copied once by C: Vector:totable).
local function as_array(v)
  if v == nil or type(v) == "table" then return v end
  return v:totable()
end

-- {======================================================================
-- What is drawn
-- =======================================================================

-- The cut below which a file weight marks a point down-weighted: trust x the median
-- (the strategies' rule, bsfit.strategy.common.trusted); nil when none is.
local function weight_cut(w, m, trust)
  if w == nil or not trust or trust <= 0 then return nil end
  local t = {}
  for i = 1, m do t[i] = w[i] end
  table.sort(t)
  local cut = trust * t[m // 2 + 1]
  return t[1] < cut and cut or nil
end

-- The residual above which at most k of the m residuals lie (a 256-bin histogram:
-- O(m), no sort of the whole array).
local function top_threshold(r, m, k)
  local hi = 0
  for i = 1, m do
    local v = r[i]
    if v > hi then hi = v end
  end
  if hi <= 0 then return math.huge end
  local bins, nb = {}, 256
  for b = 0, nb do bins[b] = 0 end
  for i = 1, m do
    local b = (r[i] / hi * nb) // 1
    if b == b then bins[b] = bins[b] + 1 end -- (a NaN residual is in no bin)
  end
  local seen = 0
  for b = nb, 0, -1 do
    seen = seen + bins[b]
    if seen > k then return (b + 1) / nb * hi end
  end
  return 0
end

-- Indices of the points to draw: all when m <= cap, else those with the largest
-- residuals (about cap / 5; residuals: a Lua array or nil) and an even subsample of the
-- rest up to cap.
function M.thin(m, residuals, cap)
  cap = cap or M.MAX_POINTS
  local idx = {}
  if m <= cap then
    for i = 1, m do idx[i] = i end
    return idx
  end
  local keep = {}
  if residuals then
    local cut = top_threshold(residuals, m, cap // 5)
    for i = 1, m do
      if residuals[i] >= cut then keep[i] = true; idx[#idx + 1] = i end
    end
  end
  local stride = math.ceil(m / (cap - #idx))
  for i = 1, m, stride do
    if not keep[i] then idx[#idx + 1] = i end
  end
  table.sort(idx)
  return idx
end

-- Every stride-th sample of S (and the last), as a Lua array of {x, y}.
local function thin_samples(S, cap, to2)
  local n, out = #S, {}
  local stride = math.max(1, math.ceil(n / cap))
  for i = 1, n, stride do out[#out + 1] = { to2(S:get(i)) } end
  if (n - 1) % stride ~= 0 then out[#out + 1] = { to2(S:get(n)) } end
  return out
end

-- The control points (Points or array of arrays) as a Lua array of {x, y}.
local function control2(ctrl, to2)
  local out = {}
  local n = type(ctrl) == "table" and #ctrl or #ctrl
  for i = 1, n do
    if type(ctrl) == "table" then out[i] = { to2(table.unpack(ctrl[i])) }
    else out[i] = { to2(ctrl:get(i)) } end
  end
  return out
end

-- The box {x0, y0, x1, y1} of the whole section (every point, the samples, the
-- control points when drawn), padded by 4% of its larger side.
local function data_box(P, to2, sets)
  P = P or {}
  local x0, y0, x1, y1 = math.huge, math.huge, -math.huge, -math.huge
  local function add(x, y)
    if x < x0 then x0 = x end
    if x > x1 then x1 = x end
    if y < y0 then y0 = y end
    if y > y1 then y1 = y end
  end
  for i = 1, #P do add(to2(P:get(i))) end -- (P may be an empty table)
  for _, s in ipairs(sets) do for _, q in ipairs(s) do add(q[1], q[2]) end end
  if x0 > x1 then x0, y0, x1, y1 = 0, 0, 1, 1 end
  local side = math.max(x1 - x0, y1 - y0)
  if side <= 0 then side = math.max(1, math.abs(x0), math.abs(y0)) end
  local pad = 0.04 * side
  -- a flat box gets a height (or width) of at least 10% of its length
  local cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
  local hw, hh = math.max(x1 - x0, 0.1 * side) / 2 + pad, math.max(y1 - y0, 0.1 * side) / 2 + pad
  return { cx - hw, cy - hh, cx + hw, cy + hh }
end

-- }======================================================================

-- {======================================================================
-- Layers (each returns a list of SVG lines; data layers are inside the flipped group)
-- =======================================================================

local function polyline(f, pts, closed, attrs)
  local t = {}
  for i, q in ipairs(pts) do t[i] = f:x(q[1]) .. "," .. f:y(q[2]) end
  return ('<%s points="%s" fill="none" %s/>'):format(closed and "polygon" or "polyline",
                                                    table.concat(t, " "), attrs)
end

local LINE = '<line x1="%s" y1="%s" x2="%s" y2="%s"/>'

-- The axes: a frame, light grid lines and tick labels (left and bottom).
local function axes(f, out, xlabel, ylabel)
  local sw = f:c(f:px(1))
  local xt, xl = plot.ticks(f.x0, f.x1, math.max(2, f.plot_w / 110))
  local yt, yl = plot.ticks(f.y0, f.y1, math.max(3, f.plot_h / 80))
  out[#out + 1] = ('<g class="grid" stroke="#e4e4e4" stroke-width="%s">'):format(sw)
  for _, x in ipairs(xt) do
    out[#out + 1] = LINE:format(f:x(x), f:y(f.y0), f:x(x), f:y(f.y1))
  end
  for _, y in ipairs(yt) do
    out[#out + 1] = LINE:format(f:x(f.x0), f:y(y), f:x(f.x1), f:y(y))
  end
  out[#out + 1] = "</g>"
  out[#out + 1] = ('<rect class="axes" x="%s" y="%s" width="%s" height="%s" fill="none" '
                   .. 'stroke="#555" stroke-width="%s"/>')
    :format(f:x(f.x0), f:y(f.y0), f:c(f.x1 - f.x0), f:c(f.y1 - f.y0), sw)
  return function(texts) -- tick labels go outside the flipped group
    texts[#texts + 1] = '<g class="ticks" fill="#333">'
    for i, x in ipairs(xt) do
      texts[#texts + 1] = f:text(x, f.y0 - f:px(4 + plot.SMALL), xl[i], plot.SMALL, "middle")
    end
    for i, y in ipairs(yt) do
      texts[#texts + 1] = f:text(f.x0 - f:px(5), y - f:px(plot.SMALL / 3), yl[i], plot.SMALL, "end")
    end
    texts[#texts + 1] = f:text((f.x0 + f.x1) / 2, f.y0 - f:px(8 + 2 * plot.SMALL), xlabel,
                               plot.SMALL, "middle")
    texts[#texts + 1] = f:text(f.x0 - f:px(8), f.y1 + f:px(6), ylabel, plot.SMALL, "end")
    texts[#texts + 1] = "</g>"
  end
end

-- The scale bar, under the x labels at the left: a nice length near a quarter of the plot.
local function scale_bar(f, texts)
  local len = plot.nice_floor((f.x1 - f.x0) / 4)
  local y = f.y0 - f:px(3 * plot.SMALL + 22)
  local x = f.x0
  texts[#texts + 1] = ('<g class="scalebar"><rect x="%s" y="%s" width="%s" height="%s" '
                       .. 'fill="#333"/>')
    :format(f:X(x), f:Y(y), f:c(len), f:c(f:px(4)))
  texts[#texts + 1] = f:text(x + len + f:px(6), y - f:px(plot.SMALL - 2),
                             ("%s (data units)"):format(plot.num(len, 6)), plot.SMALL, "start")
  texts[#texts + 1] = "</g>"
end

-- }======================================================================

-- {======================================================================
-- The section picture
-- =======================================================================

-- The section's data mapped to the plane of the picture: to2 (identity in 2D, the
-- best-fit plane in 3D), the drawn point indices, samples, control points; notes.
local function prepare(o)
  local P = o.points
  local to2, notes = function(x, y) return x, y end, {}
  if P:dim() == 3 then
    local pl = proj.plane(P)
    to2 = pl.to2
    notes[#notes + 1] = ("3D section drawn in its best-fit plane (PCA): points off it by %s RMS")
      :format(plot.num(pl.rms_off))
  end
  local d = { to2 = to2, notes = notes, m = #P }
  d.idx = M.thin(#P, o.residuals, o.max_points)
  if #d.idx < #P then
    notes[#notes + 1] = ("%d of %d points drawn (the largest residuals and an even subsample)")
      :format(#d.idx, #P)
  end
  d.samples = o.samples and thin_samples(o.samples, o.max_samples or M.MAX_SAMPLES, to2)
  d.control = o.control and control2(o.control, to2)
  local polygon = o.polygon
  if polygon == nil and d.control then polygon = #d.control <= M.DENSE_POLYGON end
  d.polygon = polygon and d.control ~= nil
  d.cut = weight_cut(o.weights, #P, o.trust == nil and 0.1 or o.trust)
  -- the colour scale: up to the largest residual of the trusted points
  local rmax = 0
  if o.residuals then
    for i = 1, #P do
      local r = o.residuals[i]
      if r > rmax and not (d.cut and o.weights[i] < d.cut) then rmax = r end
    end
  end
  d.rmax = rmax
  d.box = data_box(P, to2, { d.samples or {}, d.polygon and d.control or {} })
  return d
end

-- How many corners (C0) and tangent joins (G1) the picture marks: with pieces that say how
-- they join (rep.pieces: join, start), their joins (a join "corner" is a corner, "tangent"
-- a G1 join between pieces); else the corner samples.
local function with_joins(o)
  return o.pieces and o.pieces[1] and o.pieces[1].join ~= nil and o.pieces[1].start ~= nil
end

local function join_counts(o)
  if not with_joins(o) then return o.corners and #o.corners or 0, 0 end
  local nc, nt = 0, 0
  for _, pc in ipairs(o.pieces) do
    if pc.join == "corner" then nc = nc + 1 elseif pc.join == "tangent" and #o.pieces > 1 then nt = nt + 1 end
  end
  return nc, nt
end

-- The legend's entries {symbol, label} for what the picture holds.
local function legend_entries(o, d)
  local e = {}
  e[#e + 1] = o.residuals and { "point", "points (colour: residual)" } or { "plain", "points" }
  if d.cut then
    e[#e + 1] = { "hollow", ("down-weighted (w < %s)"):format(plot.num(d.cut)) }
  end
  if d.samples then e[#e + 1] = { "curve", "fitted curve" } end
  if d.polygon then
    e[#e + 1] = { "polygon", ("control polygon (%d)"):format(#d.control) }
  elseif d.control then
    e[#e + 1] = { "none", ("%d control points (polygon not drawn)"):format(#d.control) }
  end
  local kinds = {}
  for _, pc in ipairs(o.pieces or {}) do
    if not kinds[pc.kind] then
      kinds[pc.kind] = true
      e[#e + 1] = { "piece:" .. pc.kind, pc.kind .. " piece" }
    end
  end
  local nc, nt = join_counts(o)
  if nc > 0 then e[#e + 1] = { "corner", ("corner, C0 (%d)"):format(nc) } end
  if nt > 0 then e[#e + 1] = { "tangent", ("tangent join, G1 (%d)"):format(nt) } end
  if o.start_index then e[#e + 1] = { "start", "start point" } end
  if o.max_index then e[#e + 1] = { "max", "largest residual" } end
  return e
end

local function legend_symbol(f, kind, x, y)
  local r, sw = f:c(f:px(4)), f:c(f:px(1.5))
  local X, Y, X2 = f:X(x), f:Y(y), f:X(x + f:px(22))
  local X1 = f:X(x + f:px(11))
  local line = '<line x1="%s" y1="%s" x2="%s" y2="%s" %s/>'
  if kind == "point" or kind == "plain" then
    return ('<circle cx="%s" cy="%s" r="%s" fill="%s"/>'):format(X1, Y, r, plot.viridis(0.5))
  elseif kind == "hollow" then
    return ('<circle cx="%s" cy="%s" r="%s" fill="none" stroke="#888" stroke-width="%s"/>')
      :format(X1, Y, r, sw)
  elseif kind == "curve" then
    return line:format(X, Y, X2, Y, ('stroke="#d62728" stroke-width="%s"'):format(f:c(f:px(2))))
  elseif kind == "polygon" then
    return line:format(X, Y, X2, Y, ('stroke="#999" stroke-width="%s" stroke-dasharray="%s"')
      :format(f:c(f:px(1)), f:c(f:px(4))))
  elseif kind:match("^piece:") then
    return line:format(f:X(x + f:px(5)), Y, f:X(x + f:px(17)), Y,
      ('stroke="%s" stroke-opacity="0.35" stroke-width="%s" stroke-linecap="round"')
      :format(plot.piece_colour[kind:sub(7)] or "#999", f:c(f:px(9))))
  elseif kind == "corner" then
    local h = f:px(5)
    return ('<polygon points="%s,%s %s,%s %s,%s %s,%s" fill="#000"/>'):format(
      X1, f:Y(y + h), f:X(x + f:px(11) + h), Y, X1, f:Y(y - h), f:X(x + f:px(11) - h), Y)
  elseif kind == "tangent" then
    return ('<circle cx="%s" cy="%s" r="%s" fill="#fff" stroke="#555" stroke-width="%s"/>')
      :format(X1, Y, f:c(f:px(3)), f:c(f:px(1)))
  elseif kind == "start" then
    return ('<rect x="%s" y="%s" width="%s" height="%s" fill="none" stroke="#009e73" '
            .. 'stroke-width="%s"/>')
      :format(f:X(x + f:px(6)), f:Y(y + f:px(5)), f:c(f:px(10)), f:c(f:px(10)), f:c(f:px(2)))
  elseif kind == "max" then
    return ('<circle cx="%s" cy="%s" r="%s" fill="none" stroke="#d55e00" stroke-width="%s"/>')
      :format(X1, Y, f:c(f:px(7)), f:c(f:px(2)))
  end
  return ""
end

-- The legend and the colour bar, in the right margin from its top.
local function legend(f, o, d, entries, out)
  local x, y = f.x1 + f:px(18), f.y1 - f:px(4)
  out[#out + 1] = '<g class="legend" fill="#222">'
  for _, e in ipairs(entries) do
    y = y - f:px(20)
    out[#out + 1] = legend_symbol(f, e[1], x, y)
    out[#out + 1] = f:text(x + f:px(28), y - f:px(plot.FONT / 3), e[2], plot.FONT)
  end
  out[#out + 1] = "</g>"
  if not o.residuals then return end
  local h, w = 150, 14
  y = y - f:px(34)
  out[#out + 1] = '<g class="colorbar" fill="#222">'
  out[#out + 1] = f:text(x, y, "residual (distance to the curve)", plot.FONT)
  local top = y - f:px(12)
  out[#out + 1] = ('<rect x="%s" y="%s" width="%s" height="%s" fill="url(#viridis)" '
                   .. 'stroke="#555" stroke-width="%s"/>')
    :format(f:X(x), f:Y(top), f:c(f:px(w)), f:c(f:px(h)), f:c(f:px(0.8)))
  local ticks, labels = plot.ticks(0, d.rmax > 0 and d.rmax or 1, 4)
  for k, v in ipairs(ticks) do
    local yy = top - f:px(h) * (1 - v / (d.rmax > 0 and d.rmax or 1))
    out[#out + 1] = f:text(x + f:px(w + 6), yy - f:px(plot.SMALL / 3), labels[k], plot.SMALL)
  end
  if d.rmax > 0 and (d.rmax - ticks[#ticks]) / d.rmax * h > plot.SMALL + 3 then -- the top's value
    local label = plot.num(d.rmax)
    out[#out + 1] = f:text(x + f:px(w + 6), top - f:px(plot.SMALL / 3), label, plot.SMALL)
  end
  out[#out + 1] = "</g>"
end

local function gradient()
  local t = { '<defs><linearGradient id="viridis" x1="0" y1="1" x2="0" y2="0">' }
  for k = 0, 8 do
    t[#t + 1] = ('<stop offset="%.3f" stop-color="%s"/>'):format(k / 8, plot.viridis(k / 8))
  end
  t[#t + 1] = "</linearGradient></defs>"
  return table.concat(t)
end
-- The pieces as wide translucent bands along their points (under everything).
local function draw_pieces(f, o, d, out)
  local P, m = o.points, d.m
  for _, pc in ipairs(o.pieces or {}) do
    local pts, step = {}, math.max(1, math.ceil((pc.count or 0) / 500))
    for k = 0, (pc.count or 0) - 1, step do
      pts[#pts + 1] = { d.to2(P:get((pc.first - 1 + k) % m + 1)) }
    end
    pts[#pts + 1] = { d.to2(P:get((pc.first + pc.count - 2) % m + 1)) }
    out[#out + 1] = polyline(f, pts, false, ('class="piece-%s" stroke="%s" stroke-opacity="0.35" '
      .. 'stroke-width="%s" stroke-linecap="round" stroke-linejoin="round"')
      :format(pc.kind, plot.piece_colour[pc.kind] or "#999", f:c(f:px(9))))
  end
end

-- The points: filled by residual colour; down-weighted ones hollow and grey.
local function draw_points(f, o, d, out)
  local P, r = o.points, f:c(f:px(d.m > 2000 and 2 or 3))
  local sw = f:c(f:px(1.2))
  out[#out + 1] = '<g class="points">'
  for _, i in ipairs(d.idx) do
    local x, y = d.to2(P:get(i))
    if d.cut and o.weights[i] < d.cut then
      out[#out + 1] = ('<circle class="down" cx="%s" cy="%s" r="%s" fill="none" stroke="#888" '
                       .. 'stroke-width="%s"/>')
        :format(f:x(x), f:y(y), r, sw)
    else
      local res = o.residuals and o.residuals[i]
      local col = res and plot.viridis(d.rmax > 0 and res / d.rmax or 0) or plot.viridis(0.5)
      out[#out + 1] = ('<circle cx="%s" cy="%s" r="%s" fill="%s"/>'):format(f:x(x), f:y(y), r, col)
    end
  end
  out[#out + 1] = "</g>"
end

-- Corners (black diamonds), tangent joins between pieces (small white rings: the curve is
-- G1 there, not a corner) and the start point (green square). With pieces, the marks sit
-- where the pieces meet (a corner may lie between samples); else on the corner samples.
local function draw_marks(f, o, d, out)
  local P, h = o.points, f:px(5)
  local function diamond(x, y)
    out[#out + 1] = ('<polygon class="corner" points="%s,%s %s,%s %s,%s %s,%s" fill="#000"/>')
      :format(f:x(x), f:y(y + h), f:x(x + h), f:y(y), f:x(x), f:y(y - h), f:x(x - h), f:y(y))
  end
  if with_joins(o) then
    for _, pc in ipairs(o.pieces) do
      local x, y = pc.start[1], pc.start[2]
      if pc.join == "corner" then
        diamond(x, y)
      elseif pc.join == "tangent" and #o.pieces > 1 then
        out[#out + 1] = ('<circle class="tangent" cx="%s" cy="%s" r="%s" fill="#fff" '
                         .. 'stroke="#555" stroke-width="%s"/>')
          :format(f:x(x), f:y(y), f:c(f:px(3)), f:c(f:px(1)))
      end
    end
  else
    for _, i in ipairs(o.corners or {}) do diamond(d.to2(P:get(i))) end
  end
  if o.start_index then
    local x, y = d.to2(P:get(o.start_index))
    out[#out + 1] = ('<rect class="start" x="%s" y="%s" width="%s" height="%s" fill="none" '
                     .. 'stroke="#009e73" stroke-width="%s"/>')
      :format(f:x(x - h), f:y(y - h), f:c(2 * h), f:c(2 * h), f:c(f:px(2)))
  end
end

-- The worst residual: a ring on the point, its value in the row just above the plot
-- (so it never hides data) with a leader line, kept inside the view box.
local function draw_max(f, o, d, out, texts)
  if not o.max_index then return end
  local x, y = d.to2(o.points:get(o.max_index))
  local orange, fs = "#d55e00", plot.FONT
  out[#out + 1] = ('<circle class="max" cx="%s" cy="%s" r="%s" fill="none" stroke="%s" '
                   .. 'stroke-width="%s"/>')
    :format(f:x(x), f:y(y), f:c(f:px(7)), orange, f:c(f:px(2)))
  local down = d.cut and o.weights[o.max_index] < d.cut
  local value = o.max or (o.residuals and o.residuals[o.max_index]) or 0
  local label = ("max %s at point %d%s"):format(plot.num(value), o.max_index,
                                                down and " (down-weighted)" or "")
  local w = f:px(plot.text_width(label, fs))
  local l, _, r = f:view()
  local lx = math.max(math.min(f.x0, l + f:px(4)), math.min(x - w / 2, r - w - f:px(4)))
  lx = math.max(lx, math.min(f.x0, r - w - f:px(4)))
  local ly = f.y1 + f:px(8)
  out[#out + 1] = ('<line class="max-leader" x1="%s" y1="%s" x2="%s" y2="%s" stroke="%s" '
                   .. 'stroke-width="%s" stroke-dasharray="%s"/>')
    :format(f:x(x), f:y(y + f:px(7)), f:x(math.max(lx, math.min(x, lx + w))), f:y(ly - f:px(2)),
            orange, f:c(f:px(1)), f:c(f:px(3)))
  texts[#texts + 1] = f:text(lx, ly, label, fs, "start",
                             ('class="max-label" fill="%s" font-weight="bold"'):format(orange))
end

-- Margins (pixels) from the text they hold; the frame.
local function layout(o, d, entries)
  local box = d.box
  local size = o.size or 640
  local scale = size / math.max(box[3] - box[1], box[4] - box[2])
  local _, yl = plot.ticks(box[2], box[4], math.max(3, (box[4] - box[2]) * scale / 80))
  local left = 16
  for _, s in ipairs(yl) do left = math.max(left, plot.text_width(s, plot.SMALL) + 14) end
  local wide = plot.text_width("residual (distance to the curve)", plot.FONT)
  for _, e in ipairs(entries) do wide = math.max(wide, plot.text_width(e[2], plot.FONT)) end
  local right = 18 + 28 + wide + 12
  local lines = #d.notes + (o.subtitle and 1 or 0)
  local top = 10 + 18 + 16 * lines + 24 + (o.max_index and 22 or 0)
  local bottom = 3 * plot.SMALL + 22 + 18
  local min_w = 0
  for _, s in ipairs(d.notes) do min_w = math.max(min_w, plot.text_width(s, plot.SMALL)) end
  if o.subtitle then min_w = math.max(min_w, plot.text_width(o.subtitle, plot.SMALL)) end
  if o.title then min_w = math.max(min_w, plot.text_width(o.title, 16)) end
  local legend_h = 4 + 20 * #entries + (o.residuals and (34 + 12 + 150 + 16 + 16) or 16)
  local f = plot.frame { box = box, size = size, left = left, top = top, bottom = bottom,
                         right = right, min_height = top + legend_h }
  if f.width < min_w + 16 then -- a narrow section under a long title: widen the right margin
    f = plot.frame { box = box, size = size, left = left, top = top, bottom = bottom,
                     right = right + (min_w + 16 - f.width), min_height = top + legend_h }
  end
  return f
end

-- The title and the notes, at the top left.
local function header(f, o, d, texts)
  local l, _, _, t = f:view()
  local x, y = l + f:px(8), t - f:px(10 + 14)
  if o.title then texts[#texts + 1] = f:text(x, y, o.title, 16, "start", 'font-weight="bold"') end
  local lines = {}
  if o.subtitle then lines[1] = o.subtitle end
  for _, n in ipairs(d.notes) do lines[#lines + 1] = n end
  for _, s in ipairs(lines) do
    y = y - f:px(16)
    texts[#texts + 1] = f:text(x, y, s, plot.SMALL, "start", 'class="note" fill="#444"')
  end
end

-- The SVG text of a section picture. o: points (Points, 2D or 3D); optional residuals
-- (per point, table or Vector), weights (file weights) and trust (0.1: the strategies'
-- cut, trust x median), samples (Points on the curve), control (the distinct control
-- points), polygon (true/false; default: drawn up to 60 control points), closed,
-- start_index, max_index and max, corners (indices), pieces ({kind, first, count, join,
-- start}: with pieces, corners and tangent joins are marked where the pieces meet),
-- title, subtitle, size (pixels of the plot's longer side, 640), max_points (5000),
-- max_samples (2000).
function M.section(o)
  local copy = {}
  for k, v in pairs(o) do copy[k] = v end
  o = copy
  o.residuals, o.weights = as_array(o.residuals), as_array(o.weights)
  local d = prepare(o)
  local entries = legend_entries(o, d)
  local f = layout(o, d, entries)
  local out, texts = { f:open(), gradient() }, {}
  out[#out + 1] = f:background()
  out[#out + 1] = '<g class="data" transform="scale(1,-1)">'
  local flat = o.points:dim() == 3
  local labels = axes(f, out, flat and "u (in the plane)" or "x", flat and "v" or "y")
  draw_pieces(f, o, d, out)
  if d.polygon then
    out[#out + 1] = polyline(f, d.control, o.closed,
      ('class="control" stroke="#999" stroke-width="%s" stroke-dasharray="%s"')
      :format(f:c(f:px(1)), f:c(f:px(4))))
  end
  if d.samples then
    out[#out + 1] = polyline(f, d.samples, o.closed,
      ('class="curve" stroke="#d62728" stroke-width="%s" stroke-linejoin="round"')
      :format(f:c(f:px(2))))
  end
  draw_points(f, o, d, out)
  draw_marks(f, o, d, out)
  draw_max(f, o, d, out, texts)
  out[#out + 1] = "</g>"
  labels(out)
  scale_bar(f, out)
  header(f, o, d, out)
  legend(f, o, d, entries, out)
  for _, t in ipairs(texts) do out[#out + 1] = t end
  out[#out + 1] = "</svg>\n"
  return table.concat(out, "\n")
end

-- The SVG text of curves drawn together (bsfit filter: before and after), with axes,
-- a scale bar and a legend. o: curves (array of {samples = Points, closed, label,
-- class, colour, width (pixels), dash (pixels or nil)}), title, subtitle, size (640).
function M.curves(o)
  local sets, to2 = {}, function(x, y) return x, y end
  local all = {}
  for k, c in ipairs(o.curves) do
    sets[k] = thin_samples(c.samples, o.max_samples or M.MAX_SAMPLES, to2)
    for _, q in ipairs(sets[k]) do all[#all + 1] = q end
  end
  local d = { notes = {}, box = data_box(nil, to2, { all }) }
  local entries = {} -- the curves with a label
  for k, c in ipairs(o.curves) do
    if c.label then entries[#entries + 1] = { "line:" .. k, c.label } end
  end
  local f = layout({ size = o.size, title = o.title, subtitle = o.subtitle }, d, entries)
  local out = { f:open(), f:background(),
    '<g class="data" transform="scale(1,-1)">' }
  local labels = axes(f, out, "x", "y")
  local function style(c)
    return ('stroke="%s" stroke-width="%s"%s'):format(c.colour, f:c(f:px(c.width or 2)),
      c.dash and (' stroke-dasharray="%s"'):format(f:c(f:px(c.dash))) or "")
  end
  for k, c in ipairs(o.curves) do
    local attrs = ('class="%s" %s'):format(c.class or "curve", style(c))
    out[#out + 1] = polyline(f, sets[k], c.closed, attrs)
  end
  out[#out + 1] = "</g>"
  labels(out)
  scale_bar(f, out)
  header(f, o, d, out)
  local x, y = f.x1 + f:px(18), f.y1 - f:px(4)
  out[#out + 1] = '<g class="legend" fill="#222">'
  for _, c in ipairs(o.curves) do
    if not c.label then goto next end
    y = y - f:px(20)
    out[#out + 1] = ('<line x1="%s" y1="%s" x2="%s" y2="%s" %s/>')
      :format(f:X(x), f:Y(y), f:X(x + f:px(22)), f:Y(y), style(c))
    out[#out + 1] = f:text(x + f:px(28), y - f:px(plot.FONT / 3), c.label, plot.FONT)
    ::next::
  end
  out[#out + 1] = "</g></svg>\n"
  return table.concat(out, "\n")
end

-- The overview page (bsfit.overview).
-- The scale bar of the pictures, for other pictures in data units (bsfit.svg_surface).
M.scale_bar = scale_bar

function M.index(title, items)
  return require("bsfit.overview").page(title, items)
end

return M
