-- lua/bsfit/report.lua
-- Writing results from Lua: atomic file writes (temporary file, then rename),
-- a small deterministic JSON encoder, CSV rows, and a Lua-literal serializer used
-- to pass tables between engines (bsfit reconstruct -j).

local M = {}

-- {======================================================================
-- Files
-- =======================================================================

-- Writes data to path through path.tmp + os.rename, so a reader never sees a
-- half-written file and a failure leaves the old file untouched. Returns true,
-- or nil and a message.
function M.write_atomic(path, data)
  local tmp = path .. ".tmp"
  local f, err = io.open(tmp, "wb")
  if not f then return nil, err end
  local ok, werr = f:write(data)
  local cok, cerr = f:close()
  if not ok or not cok then
    os.remove(tmp)
    return nil, ("%s: %s"):format(path, tostring(werr or cerr))
  end
  local rok, rerr = os.rename(tmp, path)
  if not rok then
    os.remove(tmp)
    return nil, rerr
  end
  return true
end

-- Like write_atomic, but raises on failure.
function M.must_write(path, data)
  local ok, err = M.write_atomic(path, data)
  if not ok then error("cannot write " .. tostring(err), 0) end
end

-- }======================================================================

-- {======================================================================
-- Numbers and JSON
-- =======================================================================

-- A number as text that reads back to the same double; integers without ".0";
-- NaN and infinities as null (JSON has none).
function M.num(x)
  if math.type(x) == "integer" then return tostring(x) end
  if x ~= x or x == math.huge or x == -math.huge then return "null" end
  if x == math.floor(x) and math.abs(x) < 2 ^ 53 then return ("%d"):format(x) end
  return ("%.17g"):format(x)
end

local escapes = { ['"'] = '\\"', ["\\"] = "\\\\", ["\b"] = "\\b", ["\f"] = "\\f",
                  ["\n"] = "\\n", ["\r"] = "\\r", ["\t"] = "\\t" }

function M.json_string(s)
  return '"' .. s:gsub('[%c"\\]', function(c)
    return escapes[c] or ("\\u%04x"):format(c:byte())
  end) .. '"'
end

local function is_array(t)
  local n = #t
  for k in pairs(t) do
    if math.type(k) ~= "integer" or k < 1 or k > n then return false end
  end
  return true
end

-- JSON text of a value made of tables, strings, numbers, booleans (nil -> null).
-- Object keys are sorted, so equal tables give equal text.
function M.json(v)
  local t = type(v)
  if t == "nil" or v == M.null then return "null" end
  if t == "boolean" then return tostring(v) end
  if t == "number" then return M.num(v) end
  if t == "string" then return M.json_string(v) end
  if t ~= "table" then error("cannot encode a " .. t .. " as JSON", 2) end
  local parts = {}
  if is_array(v) and (#v > 0 or next(v) == nil) then
    for i = 1, #v do parts[i] = M.json(v[i]) end
    return "[" .. table.concat(parts, ",") .. "]"
  end
  local keys = {}
  for k in pairs(v) do keys[#keys + 1] = tostring(k) end
  table.sort(keys)
  for i, k in ipairs(keys) do
    local x = v[k]
    if x == nil then x = v[tonumber(k)] end
    parts[i] = M.json_string(k) .. ":" .. M.json(x)
  end
  return "{" .. table.concat(parts, ",") .. "}"
end

-- The value of a JSON text (objects as tables, arrays as sequences, null as nil),
-- for reading back what M.json wrote (bsfit merge). Returns the value, or nil and a
-- message with the byte offset.
function M.json_decode(s)
  local pos = 1
  local function fail(what) error(("JSON: %s at byte %d"):format(what, pos), 0) end
  local function ws() pos = s:find("[^ \t\r\n]", pos) or #s + 1 end
  local value
  local function str()
    local out = {}
    pos = pos + 1
    while true do
      local a, b = s:find('["\\]', pos)
      if not a then fail("unterminated string") end
      out[#out + 1] = s:sub(pos, a - 1)
      if s:sub(a, a) == '"' then pos = b + 1; break end
      local c = s:sub(a + 1, a + 1)
      local simple = { b = "\b", f = "\f", n = "\n", r = "\r", t = "\t", ['"'] = '"',
                       ["\\"] = "\\", ["/"] = "/" }
      if simple[c] then out[#out + 1] = simple[c]; pos = a + 2
      elseif c == "u" then
        local hex = s:match("^%x%x%x%x", a + 2) or fail("bad \\u escape")
        out[#out + 1] = utf8.char(tonumber(hex, 16)); pos = a + 6
      else fail("bad escape") end
    end
    return table.concat(out)
  end
  local function container(close, item)
    pos = pos + 1
    ws()
    if s:sub(pos, pos) == close then pos = pos + 1; return end
    while true do
      item()
      ws()
      local c = s:sub(pos, pos)
      pos = pos + 1
      if c == close then return end
      if c ~= "," then fail("expected ',' or '" .. close .. "'") end
    end
  end
  function value()
    ws()
    local c = s:sub(pos, pos)
    if c == "{" then
      local t = {}
      container("}", function()
        ws()
        if s:sub(pos, pos) ~= '"' then fail("expected a key") end
        local k = str()
        ws()
        if s:sub(pos, pos) ~= ":" then fail("expected ':'") end
        pos = pos + 1
        t[k] = value()
      end)
      return t
    elseif c == "[" then
      local t = {}
      container("]", function() t[#t + 1] = value() end)
      return t
    elseif c == '"' then return str()
    end
    for word, v in pairs { ["true"] = true, ["false"] = false, null = M.null } do
      if s:sub(pos, pos + #word - 1) == word then pos = pos + #word; return v end
    end
    local num = s:match("^-?%d+%.?%d*[eE]?[-+]?%d*", pos)
    if not num or num == "" or not tonumber(num) then fail("unexpected character") end
    pos = pos + #num
    return tonumber(num)
  end
  local ok, v = pcall(function()
    local r = value()
    ws()
    if pos <= #s then fail("trailing text") end
    return r
  end)
  if not ok then return nil, v end
  return v
end

-- JSON's null as json_decode returns it inside arrays and objects: a value that is
-- not nil, so that arrays keep their length; M.unnull turns it into nil.
M.null = setmetatable({}, { __tostring = function() return "null" end })

-- }======================================================================

-- {======================================================================
-- CSV
-- =======================================================================

-- One CSV field: quoted when it holds a comma, quote or line break.
function M.csv_field(v)
  if v == M.null then return "" end
  if type(v) == "number" then return M.num(v) == "null" and "" or M.num(v) end
  v = tostring(v == nil and "" or v)
  if v:find('[,"\r\n]') then return '"' .. v:gsub('"', '""') .. '"' end
  return v
end

-- CSV text of rows (arrays of tables) with the given columns, header first.
function M.csv(columns, rows)
  local out = { table.concat(columns, ",") }
  for _, r in ipairs(rows) do
    local f = {}
    for i, c in ipairs(columns) do f[i] = M.csv_field(r[c]) end
    out[#out + 1] = table.concat(f, ",")
  end
  return table.concat(out, "\n") .. "\n"
end

-- }======================================================================

-- {======================================================================
-- Lua literals (for passing plain tables between Lua states)
-- =======================================================================

-- Lua source of a value made of tables, strings, numbers and booleans.
function M.serialize(v)
  local t = type(v)
  if t == "string" then return ("%q"):format(v) end
  if t == "number" then
    if math.type(v) == "integer" then return ("%d"):format(v) end
    if v ~= v then return "(0/0)" end
    if v == math.huge then return "math.huge" end
    if v == -math.huge then return "(-math.huge)" end
    return ("%.17g"):format(v)
  end
  if t == "boolean" or t == "nil" then return tostring(v) end
  if t ~= "table" then error("cannot serialize a " .. t, 2) end
  local keys, parts = {}, {}
  for k in pairs(v) do keys[#keys + 1] = k end
  table.sort(keys, function(a, b) return tostring(a) < tostring(b) end)
  for _, k in ipairs(keys) do
    parts[#parts + 1] = "[" .. M.serialize(k) .. "]=" .. M.serialize(v[k])
  end
  return "{" .. table.concat(parts, ",") .. "}"
end

-- The value of a string made by serialize (evaluated as data: no globals but math).
function M.deserialize(s)
  local f, err = load("return " .. s, "=serialized", "t", { math = { huge = math.huge } })
  if not f then error("bad serialized value: " .. err, 2) end
  return f()
end

-- }======================================================================

return M
