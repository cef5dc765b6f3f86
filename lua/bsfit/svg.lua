-- lua/bsfit/svg.lua
-- The picture of one fitted section: the input points, the curve, its control
-- polygon (dashed) and labelled markers (start point, worst residual), as SVG
-- text. The data's bounding box is mapped to the picture with the y axis up.
--
--   local svg = require "bsfit.svg"
--   local text = svg.section{points = P, curve = C, samples = S,
--                            markers = {{x, y, "start"}, ...}, title = "cam"}

local M = {}

local function fmt(x) return ("%.2f"):format(x) end

local function escape(s)
  return (tostring(s):gsub("[<>&\"]", { ["<"] = "&lt;", [">"] = "&gt;", ["&"] = "&amp;",
                                         ['"'] = "&quot;" }))
end

-- Bounding box of the x, y of a list of Points / arrays of {x, y}.
local function bbox(sets)
  local x0, y0, x1, y1 = math.huge, math.huge, -math.huge, -math.huge
  for _, s in ipairs(sets) do
    for i = 1, #s do
      local x, y
      if type(s) == "table" then x, y = s[i][1], s[i][2] else x, y = s:get(i) end
      if x == x and y == y then
        x0, y0 = math.min(x0, x), math.min(y0, y)
        x1, y1 = math.max(x1, x), math.max(y1, y)
      end
    end
  end
  if x0 > x1 then return 0, 0, 1, 1 end
  if x1 - x0 == 0 then x0, x1 = x0 - 0.5, x1 + 0.5 end
  if y1 - y0 == 0 then y0, y1 = y0 - 0.5, y1 + 0.5 end
  return x0, y0, x1, y1
end

-- A mapping from data to picture coordinates for the given width and margin.
local function mapping(sets, width, margin)
  local x0, y0, x1, y1 = bbox(sets)
  local s = (width - 2 * margin) / math.max(x1 - x0, y1 - y0)
  local w, h = (x1 - x0) * s + 2 * margin, (y1 - y0) * s + 2 * margin
  return function(x, y) return (x - x0) * s + margin, (y1 - y) * s + margin end, w, h
end

-- "x,y x,y ..." of a Points or an array of {x, y} through map.
local function path(set, map)
  local out = {}
  for i = 1, #set do
    local x, y
    if type(set) == "table" then x, y = set[i][1], set[i][2] else x, y = set:get(i) end
    local X, Y = map(x, y)
    out[i] = fmt(X) .. "," .. fmt(Y)
  end
  return table.concat(out, " ")
end

local style = [[
<style>
 .points circle{fill:#1f77b4}
 .curve{fill:none;stroke:#d62728;stroke-width:1.5}
 .control{fill:none;stroke:#7f7f7f;stroke-width:0.8;stroke-dasharray:4 3}
 .control circle{fill:#7f7f7f;stroke:none}
 .marker circle{fill:none;stroke:#2ca02c;stroke-width:2}
 .marker text{font:12px sans-serif;fill:#2ca02c}
 .title{font:14px sans-serif;fill:#333}
</style>
]]

-- SVG text of a section. o: points (Points), samples (Points of curve samples),
-- control (array of {x, y}, the distinct control points), closed (draw the curve
-- and the control polygon closed), markers (array of {x, y, label}), title,
-- width (600).
function M.section(o)
  local width, margin, r = o.width or 600, 24, 2.5
  local sets = { o.points }
  if o.samples then sets[#sets + 1] = o.samples end
  if o.control then sets[#sets + 1] = o.control end
  local map, w, h = mapping(sets, width, margin)
  local out = {
    ('<svg xmlns="http://www.w3.org/2000/svg" width="%s" height="%s" viewBox="0 0 %s %s">')
      :format(fmt(w), fmt(h), fmt(w), fmt(h)),
    style,
  }
  if o.title then
    out[#out + 1] = ('<text class="title" x="4" y="16">%s</text>'):format(escape(o.title))
  end
  local shape = o.closed and "polygon" or "polyline"
  if o.control then
    out[#out + 1] = ('<g class="control"><%s points="%s"/></g>'):format(shape, path(o.control, map))
  end
  if o.samples then
    out[#out + 1] = ('<%s class="curve" points="%s"/>'):format(shape, path(o.samples, map))
  end
  out[#out + 1] = '<g class="points">'
  for i = 1, #o.points do
    local X, Y = map(o.points:get(i))
    out[#out + 1] = ('<circle cx="%s" cy="%s" r="%s"/>'):format(fmt(X), fmt(Y), fmt(r))
  end
  out[#out + 1] = "</g>"
  for _, mk in ipairs(o.markers or {}) do
    local X, Y = map(mk[1], mk[2])
    out[#out + 1] = ('<g class="marker"><circle cx="%s" cy="%s" r="6"/><text x="%s" y="%s">%s</text></g>')
      :format(fmt(X), fmt(Y), fmt(X + 8), fmt(Y - 8), escape(mk[3] or ""))
  end
  out[#out + 1] = "</svg>\n"
  return table.concat(out, "\n")
end

-- An HTML page showing the given SVG files (names relative to the page), with a
-- caption each.
function M.index(title, items)
  local out = { "<!DOCTYPE html>", '<html><head><meta charset="utf-8"><title>' .. escape(title)
                .. "</title>", "<style>figure{display:inline-block;margin:8px;border:1px solid #ddd}"
                .. "img{width:320px}figcaption{font:12px sans-serif;padding:4px}</style></head><body>",
                "<h1>" .. escape(title) .. "</h1>" }
  for _, it in ipairs(items) do
    if it.svg then
      out[#out + 1] = ('<figure><img src="%s" alt="%s"><figcaption>%s</figcaption></figure>')
        :format(escape(it.svg), escape(it.name), escape(it.caption or it.name))
    else
      out[#out + 1] = ('<figure><figcaption>%s</figcaption></figure>'):format(escape(it.caption or it.name))
    end
  end
  out[#out + 1] = "</body></html>\n"
  return table.concat(out, "\n")
end

return M
