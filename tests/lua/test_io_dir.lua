-- test_io_dir.lua: bs.io (directories without a shell): listdir sorted by bytes with
-- any byte in a name, the fail triple for a missing or non-directory path, kind, mkdir -p.
local T = require "tap"
local bs = require "bsfit"

local function tmpdir()
  local base = os.tmpname()
  os.remove(base)
  assert(bs.io.mkdir(base))
  return base
end

local function touch(path)
  local f = assert(io.open(path, "wb"))
  f:close()
end

T.test("listdir: every name, sorted by bytes, newlines and spaces included", function()
  local d = tmpdir()
  local made = { "b.csv", "a.csv", "with\nnewline.csv", " lead", "Z", "\xc3\xa9t\xc3\xa9.xy" }
  for _, n in ipairs(made) do touch(d .. "/" .. n) end
  bs.io.mkdir(d .. "/sub")
  local names = bs.io.listdir(d)
  local want = { "sub" }
  for _, n in ipairs(made) do want[#want + 1] = n end
  table.sort(want) -- Lua compares strings by bytes in the C locale
  T.eq(#names, #want)
  for i = 1, #want do T.eq(names[i], want[i]) end
  T.eq(bs.io.kind(d .. "/sub"), "directory")
  T.eq(bs.io.kind(d .. "/a.csv"), "file")
  T.eq(bs.io.kind(d .. "/none"), nil)
  for _, n in ipairs(made) do os.remove(d .. "/" .. n) end
  os.remove(d .. "/sub")
  T.eq(#bs.io.listdir(d), 0)
  os.remove(d)
end)

T.test("listdir and mkdir fail with nil, message, EIO", function()
  local r, msg, code = bs.io.listdir("/nonexistent/dir/")
  T.eq(r, nil)
  T.eq(msg, "cannot list /nonexistent/dir/: No such file or directory")
  T.eq(code, "EIO")
  local d = tmpdir()
  touch(d .. "/f")
  r, msg, code = bs.io.listdir(d .. "/f")
  T.eq(code, "EIO")
  T.ok(msg:find("Not a directory", 1, true), msg)
  T.eq(bs.io.mkdir(d .. "/m/n/o/"), true)
  T.eq(bs.io.kind(d .. "/m/n/o"), "directory")
  T.eq(bs.io.mkdir(d .. "/m/n/o"), true)
  r, msg, code = bs.io.mkdir(d .. "/f/g")
  T.eq(r, nil)
  T.eq(msg, d .. "/f is not a directory (making " .. d .. "/f/g)")
  T.eq(code, "EIO")
  T.raises("bad argument #1 to 'listdir' (string expected, got no value)",
           function() bs.io.listdir() end)
  for _, p in ipairs { "/m/n/o", "/m/n", "/m", "/f", "" } do os.remove(d .. p) end
end)
