-- lua/bsfit/plot.lua
-- The frame of a picture in data units (docs/pictures.md): an SVG whose viewBox is in
-- the data's coordinates with y up. Data are drawn inside a group with
-- transform="scale(1,-1)", so a point (x, y) is written as it is, less the picture's
-- origin and in its unit (the svg element's data-origin="ox oy" and data-unit="u": x is
-- ox + u * the number written). The origin is 0 0 unless the data lie farther from 0
-- than 1000 times their size (renderers that draw in single precision, Skia and cairo
-- among them, would shake the curve by pixels), then a round number near the data's
-- centre; the unit is 1 unless the size is below 0.01 or above 1e6 (librsvg draws
-- nothing in a viewBox of 0.001), then a power of ten near the size. Text is written
-- outside that group at (x, -y), so it reads the right way up. Sizes meant in pixels
-- (strokes, radii, margins) are divided by the scale (pixels per data unit). Text is
-- laid out in pixels: each <text> is moved to its data position and scaled by 1/scale
-- (a font of 0.1 data units would be hinted at 0.1 pixels by renderers such as
-- librsvg, and its letters spaced at random).
--
--   local plot = require "bsfit.plot"
--   local f = plot.frame{box = {x0, y0, x1, y1}, size = 640, right = 200, top = 40}
--   f:px(12) -- 12 pixels in data units;  f:c(len) -- a length as text
--   f:x(x), f:y(y) -- positions in the flipped group;  f:X(x), f:Y(y) -- outside it
-- Also: the viridis colour map, nice axis ticks, number formatting, text widths.

local M = {}

M.FONT = 13 -- pixels
M.SMALL = 11

-- {======================================================================
-- Numbers and text
-- =======================================================================

-- A number with g digits, without a trailing exponent mess ("0.0123", "1.5e+06").
function M.num(x, g)
  if x ~= x then return "nan" end
  return (("%." .. (g or 3) .. "g"):format(x))
end

-- Estimated width in pixels of text at font size fs (sans-serif averages ~0.6 em;
-- 0.62 keeps a little slack so estimated boxes are never too small).
function M.text_width(s, fs)
  return #tostring(s) * 0.62 * (fs or M.FONT)
end

function M.escape(s)
  return (tostring(s):gsub("[<>&\"']", { ["<"] = "&lt;", [">"] = "&gt;", ["&"] = "&amp;",
                                          ['"'] = "&quot;", ["'"] = "&apos;" }))
end

-- A "nice" step (1, 2 or 5 times a power of ten) near span / n.
function M.nice_step(span, n)
  local raw = span / n
  local p = 10 ^ math.floor(math.log(raw, 10))
  for _, k in ipairs({ 1, 2, 5, 10 }) do
    if k * p >= raw then return k * p end
  end
  return 10 * p
end

-- The largest "nice" number (1, 2 or 5 times a power of ten) not above x > 0.
function M.nice_floor(x)
  local p = 10 ^ math.floor(math.log(x, 10))
  for _, k in ipairs({ 5, 2, 1 }) do
    if k * p <= x * (1 + 1e-12) then return k * p end
  end
  return p
end

-- Ticks (multiples of a nice step) within [a, b], about n of them; and their labels
-- with just the decimals the step needs.
function M.ticks(a, b, n)
  local step = M.nice_step(b - a, n)
  local dec = math.max(0, -math.floor(math.log(step, 10) + 1e-9))
  local t, labels = {}, {}
  for k = math.ceil(a / step - 1e-9), math.floor(b / step + 1e-9) do
    local v = k * step
    t[#t + 1] = v
    -- fixed decimals read best; past 4 of them (tiny residuals), "1e-12" reads better
    local label = dec <= 4 and ("%." .. dec .. "f"):format(v) or ("%.3g"):format(v)
    labels[#labels + 1] = math.abs(v) < step * 1e-9 and "0" or label
  end
  return t, labels, step
end

-- }======================================================================

-- {======================================================================
-- Colours
-- =======================================================================

-- Viridis (perceptually uniform, readable with the common colour-vision deficiencies
-- and in grey), as 9 anchors interpolated linearly.
local viridis = {
  { 68, 1, 84 }, { 72, 40, 120 }, { 62, 74, 137 }, { 49, 104, 142 }, { 38, 130, 142 },
  { 31, 158, 137 }, { 53, 183, 121 }, { 110, 206, 88 }, { 253, 231, 37 },
}

-- The colour of t in [0, 1] as "#rrggbb".
function M.viridis(t)
  if t ~= t then t = 0 end
  t = math.min(1, math.max(0, t)) * (#viridis - 1)
  local i = math.min(#viridis - 2, math.floor(t))
  local f, a, b = t - i, viridis[i + 1], viridis[i + 2]
  local c = {}
  for k = 1, 3 do c[k] = math.floor(a[k] + (b[k] - a[k]) * f + 0.5) end
  return ("#%02x%02x%02x"):format(c[1], c[2], c[3])
end

-- Colours of the pieces of a section (Okabe-Ito: distinguishable by colour-blind readers).
M.piece_colour = { line = "#0072b2", arc = "#e69f00", free = "#cc79a7" }

-- }======================================================================

-- {======================================================================
-- The frame
-- =======================================================================

local Frame = {}
Frame.__index = Frame

-- o.box = {x0, y0, x1, y1}: the plot area in data units (already padded); o.size: the
-- pixels of its longer side; o.left, o.right, o.top, o.bottom: margins in pixels;
-- o.min_height: the least height of the whole picture in pixels.
function M.frame(o)
  local b = o.box
  local f = setmetatable({ x0 = b[1], y0 = b[2], x1 = b[3], y1 = b[4] }, Frame)
  f.scale = o.size / math.max(b[3] - b[1], b[4] - b[2])
  f.left, f.right, f.top, f.bottom = o.left or 0, o.right or 0, o.top or 0, o.bottom or 0
  f.plot_w, f.plot_h = (b[3] - b[1]) * f.scale, (b[4] - b[2]) * f.scale
  f.width = f.left + f.plot_w + f.right
  f.height = math.max(f.top + f.plot_h + f.bottom, o.min_height or 0)
  local extent = math.max(b[3] - b[1], b[4] - b[2])
  f.ox, f.oy = M.origin((b[1] + b[3]) / 2, extent), M.origin((b[2] + b[4]) / 2, extent)
  f.unit_exp = (extent < 1e-2 or extent > 1e6) and math.floor(math.log(extent, 10)) or 0
  f.unit = 10.0 ^ f.unit_exp
  -- digits that keep 1/10000 of the picture's size exact
  f.dec = math.max(0, math.min(15, math.ceil(-math.log(extent / f.unit, 10)) + 5))
  return f
end

-- The origin of a picture's coordinates along one axis: 0, or for data centred at c
-- farther than 1000 extents from 0, c rounded to a power of ten at least the extent.
function M.origin(c, extent)
  if math.abs(c) <= 1000 * extent then return 0 end
  local step = 10 ^ math.ceil(math.log(extent, 10))
  return math.floor(c / step + 0.5) * step
end

function Frame:px(p) return p / self.scale end

-- A length in data units as text in the picture's unit (fixed decimals fitted to its size).
function Frame:c(v) return ("%." .. self.dec .. "f"):format(v / self.unit) end

-- Positions of data (x, y) inside the flipped group, relative to the origin.
function Frame:x(x) return self:c(x - self.ox) end
function Frame:y(y) return self:c(y - self.oy) end

-- Positions of data (x, y) outside the flipped group (text, legend): y is -y.
function Frame:X(x) return self:c(x - self.ox) end
function Frame:Y(y) return self:c(self.oy - y) end

-- Data coordinates of the picture's corners (left, bottom, right, top).
function Frame:view()
  local l = self.x0 - self:px(self.left)
  local t = self.y1 + self:px(self.top)
  return l, t - self:px(self.height), l + self:px(self.width), t
end

-- The opening <svg> element: viewBox in data units (y of the box is -top).
function Frame:open()
  local l, _, _, t = self:view()
  return ('<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="%s %s %s %s" '
          .. 'data-origin="%s %s" data-unit="%s" font-family="sans-serif">')
    :format(math.ceil(self.width), math.ceil(self.height), self:X(l), self:Y(t),
            self:c(self:px(self.width)), self:c(self:px(self.height)),
            M.num(self.ox, 17), M.num(self.oy, 17), ("1e%d"):format(self.unit_exp))
end

-- A white rectangle under the whole picture (outside the flipped group).
function Frame:background()
  local l, _, _, t = self:view()
  return ('<rect class="background" x="%s" y="%s" width="%s" height="%s" fill="#fff"/>')
    :format(self:X(l), self:Y(t), self:c(self:px(self.width)), self:c(self:px(self.height)))
end

-- A text element at data (x, y); size in pixels; anchor start|middle|end; extra attrs.
-- Laid out in pixels, then scaled to data units (see the top of this file).
function Frame:text(x, y, s, size, anchor, attrs)
  return ('<text transform="translate(%s,%s) scale(%s)" font-size="%s" text-anchor="%s"%s>%s</text>')
    :format(self:X(x), self:Y(y), ("%.9g"):format(1 / (self.scale * self.unit)),
            M.num(size or M.FONT, 6), anchor or "start", attrs and (" " .. attrs) or "",
            M.escape(s))
end

-- }======================================================================

return M
