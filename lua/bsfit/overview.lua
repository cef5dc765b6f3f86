-- lua/bsfit/overview.lua
-- The overview page of a batch (index.html, docs/pictures.md): one self-contained HTML
-- file, no external files. A table of the sections (picture, name, points, control
-- points, RMS, max, status, warnings), failed sections first, sorted by a click on a
-- column header (plain inline JavaScript); each thumbnail links to the full picture.
--
--   local overview = require "bsfit.overview"
--   local html = overview.page("bsfit reconstruct", rows)
-- rows: {name, svg (file name or nil), points, control_points, rms, max, status,
-- error, warnings} as in summary.json.

local plot = require "bsfit.plot"

local M = {}

local esc = plot.escape

local style = [[
body{font:14px sans-serif;margin:16px;color:#222}
h1{font-size:20px;margin:0 0 4px}
p.totals{margin:0 0 12px;color:#444}
table{border-collapse:collapse}
th,td{border:1px solid #ccc;padding:4px 8px;vertical-align:middle}
th{background:#f0f0f0;cursor:pointer;user-select:none;white-space:nowrap}
th.sorted-up::after{content:" \25B2"}
th.sorted-down::after{content:" \25BC"}
td.num{text-align:right;font-variant-numeric:tabular-nums}
tr.error td{background:#fde8e8}
tr.error td.status{color:#b00020;font-weight:bold}
td.pic img{width:600px;max-width:60vw;display:block;background:#fff}
td.msg{max-width:260px}]]

-- Sorts the table by the clicked column: numbers as numbers (data-v), text as text;
-- a second click reverses.
local script = [[
document.querySelectorAll("th").forEach(function (th, col) {
  th.addEventListener("click", function () {
    var tbody = th.closest("table").tBodies[0];
    var up = !th.classList.contains("sorted-up");
    document.querySelectorAll("th").forEach(function (h) {
      h.classList.remove("sorted-up", "sorted-down");
    });
    th.classList.add(up ? "sorted-up" : "sorted-down");
    var rows = Array.prototype.slice.call(tbody.rows);
    rows.sort(function (a, b) {
      var x = a.cells[col].getAttribute("data-v"), y = b.cells[col].getAttribute("data-v");
      var nx = parseFloat(x), ny = parseFloat(y), r;
      if (!isNaN(nx) && !isNaN(ny)) r = nx - ny; else r = String(x).localeCompare(String(y));
      return up ? r : -r;
    });
    rows.forEach(function (r) { tbody.appendChild(r); });
  });
});]]

local function numcell(v, fmt)
  if type(v) ~= "number" then return '<td class="num" data-v="">&ndash;</td>' end
  return ('<td class="num" data-v="%.17g">%s</td>'):format(v, fmt and fmt:format(v) or tostring(v))
end

local function row_html(r)
  local ok = r.status == "ok"
  local pic = '<td class="pic" data-v="">no picture</td>'
  if r.svg then
    pic = ('<td class="pic" data-v="%s"><a href="%s"><img src="%s" alt="%s" loading="lazy">'
           .. '</a></td>')
      :format(esc(r.name), esc(r.svg), esc(r.svg), esc(r.name))
  end
  local name = r.svg and ('<a href="%s">%s</a>'):format(esc(r.svg), esc(r.name)) or esc(r.name)
  local warn = ok and (r.warnings or "") or (r.error or "")
  return table.concat {
    ('<tr class="%s">'):format(ok and "ok" or "error"), pic,
    ('<td data-v="%s">%s</td>'):format(esc(r.name), name),
    numcell(r.points), numcell(r.control_points), numcell(r.rms, "%.3g"), numcell(r.max, "%.3g"),
    ('<td class="status" data-v="%s">%s</td>'):format(ok and "1" or "0", esc(r.status)),
    ('<td class="msg" data-v="%s">%s</td>'):format(esc(warn), esc(warn)), "</tr>" }
end

-- The rows in page order: failed sections first, then the others, each group in the
-- given (input) order.
function M.order(rows)
  local out = {}
  for _, r in ipairs(rows) do if r.status ~= "ok" then out[#out + 1] = r end end
  for _, r in ipairs(rows) do if r.status == "ok" then out[#out + 1] = r end end
  return out
end

-- The HTML text of the page.
function M.page(title, rows)
  local failed, warned = 0, 0
  for _, r in ipairs(rows) do
    if r.status ~= "ok" then failed = failed + 1
    elseif r.warnings and r.warnings ~= "" then warned = warned + 1 end
  end
  local out = {
    "<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
    "<title>" .. esc(title) .. "</title>", "<style>" .. style .. "</style></head><body>",
    "<h1>" .. esc(title) .. "</h1>",
    ('<p class="totals">%d sections: %d ok, %d failed, %d with warnings. Click a column header '
     .. 'to sort; click a picture to open it at full size.</p>')
      :format(#rows, #rows - failed, failed, warned),
    "<table><thead><tr><th>picture</th><th>name</th><th>points</th><th>control points</th>"
      .. "<th>RMS</th><th>max</th><th>status</th><th>warnings / error</th></tr></thead><tbody>" }
  for _, r in ipairs(M.order(rows)) do out[#out + 1] = row_html(r) end
  out[#out + 1] = "</tbody></table>"
  out[#out + 1] = "<script>" .. script .. "</script>"
  out[#out + 1] = "</body></html>\n"
  return table.concat(out, "\n")
end

return M
