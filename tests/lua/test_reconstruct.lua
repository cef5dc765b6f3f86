-- test_reconstruct.lua: bsfit.cli.reconstruct (arguments, inputs, one section),
-- bsfit.report (JSON, CSV, serializer, atomic writes) and bsfit.svg
local T = require "tap"
local bs = require "bsfit"
local rc = require "bsfit.cli.reconstruct"
local report = require "bsfit.report"
local svg = require "bsfit.svg"

local SRC = (arg and arg[1] or ""):match("^(.*)/tests/lua/[^/]*$") or os.getenv("BSFIT_SOURCE_DIR") or "."

local function tmpdir()
  local d = os.tmpname()
  os.remove(d)
  os.execute("mkdir -p '" .. d .. "'")
  return d
end

local function slurp(path)
  local f = io.open(path, "rb")
  if not f then return nil end
  local s = f:read("a")
  f:close()
  return s
end

T.test("parse: defaults and every option", function()
  local o = rc.parse {}
  T.eq(o.strategy, "auto"); T.eq(o.degree, 3); T.eq(o.samples, 1000); T.eq(o.jobs, 1)
  T.eq(o.outdir, "bsfit-out"); T.eq(o.count, nil)
  T.ok(o.formats.json and o.formats.svg and o.formats.csv and not o.formats.iges)
  o = rc.parse { "a.csv", "-o", "out", "--strategy", "carvalho", "--degree", "2", "--count", "12",
                 "--samples=50", "--format", "json,iges", "-j", "4", "dir" }
  T.eq(o.outdir, "out"); T.eq(o.strategy, "carvalho"); T.eq(o.degree, 2); T.eq(o.count, 12)
  T.eq(o.samples, 50); T.eq(o.jobs, 4); T.ok(o.formats.iges and not o.formats.svg)
  T.eq(#o.inputs, 2); T.eq(o.inputs[2], "dir")
  T.eq(rc.parse { "--count", "auto" }.count, nil)
  o = rc.parse { "--tol", "0.01", "--open" }
  T.eq(o.tol, 0.01); T.eq(o.open, true)
end)

T.test("parse: bad arguments raise with a message", function()
  T.raises("unknown option '--bogus'", function() rc.parse { "--bogus" } end)
  T.raises("option -o needs a value", function() rc.parse { "-o" } end)
  T.raises("--count must be a positive integer, got '0'", function() rc.parse { "--count", "0" } end)
  T.raises("-j must be a positive integer, got 'x'", function() rc.parse { "-j", "x" } end)
  T.raises("unknown format 'png' (json, svg, csv, iges, step, dxf)", function() rc.parse { "--format", "png" } end)
  T.raises("--tol needs --strategy auto or periodic (or a FILE.lua)", function()
    rc.parse { "--strategy", "carvalho", "--tol", "1" } end)
  T.raises("--samples must be at least 2", function() rc.parse { "--samples", "1" } end)
  T.raises({ match = "^%-%-tol must be a number" }, function() rc.parse { "--tol", "-1" } end)
end)

T.test("inputs: a directory gives its point files, sorted, with unique names", function()
  local ins = rc.inputs { SRC .. "/tests/data/demo", SRC .. "/tests/data/demo/cam.csv" }
  T.eq(#ins, 6)
  local names = {}
  for i, s in ipairs(ins) do names[i] = s.name end
  T.eq(table.concat(names, " "), "airfoil bracket cam knob_weighted noisy_blob cam_2")
end)

T.test("section: a good file gives its files and an ok row", function()
  local d = tmpdir()
  local row = rc.section { path = SRC .. "/tests/data/demo/cam.csv", name = "cam", outdir = d,
                           strategy = "periodic", degree = 3, samples = 20,
                           formats = { json = true, svg = true, csv = true } }
  T.eq(row.status, "ok", row.error)
  T.eq(row.points, 180)
  T.ok(row.control_points >= 4 and row.max >= row.rms and row.rms >= 0)
  local csv = slurp(d .. "/cam.csv")
  local lines = 0
  for _ in csv:gmatch("\n") do lines = lines + 1 end
  T.eq(lines, 21, "header + 20 samples")
  local C = bs.curve.from_json and bs.curve.from_json(slurp(d .. "/cam.json"))
  if C then T.eq(C:distinct(), row.control_points) end
  local pic = slurp(d .. "/cam.svg")
  T.ok(pic:find("<svg", 1, true) and pic:find(">start point<", 1, true) and pic:find(">max ", 1, true),
       "the picture marks the start point and the worst residual")
  os.execute("rm -rf '" .. d .. "'")
end)

T.test("section: a broken file gives an error row and no file", function()
  local d = tmpdir()
  for _, bad in ipairs { "text", "nan", "two_points", "empty" } do
    local row = rc.section { path = SRC .. "/tests/data/bad/" .. bad .. ".csv", name = bad, outdir = d,
                             strategy = "carvalho", degree = 3, samples = 10, formats = { json = true } }
    T.eq(row.status, "error", bad)
    T.ok(#row.error > 0, bad .. ": a message")
    T.eq(slurp(d .. "/" .. bad .. ".json"), nil, bad .. ": no curve")
  end
  local row = rc.section { path = d .. "/missing.csv", name = "missing", outdir = d, strategy = "periodic",
                           degree = 3, samples = 10, formats = { json = true } }
  T.eq(row.status, "error")
  os.execute("rm -rf '" .. d .. "'")
end)

T.test("report.json: sorted keys, arrays, escapes, exact numbers", function()
  T.eq(report.json { b = 1, a = { 1, 2.5, "x\n" }, c = true }, '{"a":[1,2.5,"x\\n"],"b":1,"c":true}')
  T.eq(report.json {}, "[]")
  T.eq(report.json(0 / 0), "null")
  local x = 0.1 + 0.2
  T.eq(tonumber(report.json(x)), x, "round trip")
end)

T.test("report.csv: header, quoting, empty fields", function()
  T.eq(report.csv({ "a", "b" }, { { a = 1, b = 'say "hi", ok' }, { a = 2.5 } }),
       'a,b\n1,"say ""hi"", ok"\n2.5,\n')
end)

T.test("report.serialize: round trip of nested tables", function()
  local v = { name = "x\0y", n = 3, f = 1 / 3, t = { 1, 2, { deep = true } }, inf = math.huge }
  local w = report.deserialize(report.serialize(v))
  T.eq(w.name, v.name); T.eq(w.n, 3); T.eq(math.type(w.n), "integer"); T.eq(w.f, v.f)
  T.eq(w.t[3].deep, true); T.eq(w.inf, math.huge)
  T.eq(report.serialize(v), report.serialize(w), "deterministic text")
end)

T.test("report.write_atomic: replaces the file, leaves no temporary", function()
  local d = tmpdir()
  T.ok(report.write_atomic(d .. "/f.txt", "one"))
  T.ok(report.write_atomic(d .. "/f.txt", "two"))
  T.eq(slurp(d .. "/f.txt"), "two")
  T.eq(slurp(d .. "/f.txt.tmp"), nil)
  local ok, err = report.write_atomic(d .. "/no/such/dir/f.txt", "x")
  T.eq(ok, nil); T.ok(type(err) == "string")
  os.execute("rm -rf '" .. d .. "'")
end)

T.test("the demo set is found next to the lua directory", function()
  if os.getenv("BSFIT_DEMO_DIR") then return end
  local d = rc.demo_dir()
  T.ok(d:match("tests/data/demo$"), d)
  T.ok(slurp(d .. "/cam.csv"), "cam.csv in " .. d)
end)

T.test("section: --open and a strategy FILE.lua", function()
  local d = tmpdir()
  local f = io.open(d .. "/mine.lua", "w")
  f:write('local p = require "bsfit.strategy.periodic"\n',
          'return { run = function(P, o) o.count = 10; return p.run(P, o) end }\n')
  f:close()
  local spec = { path = SRC .. "/tests/data/demo/bracket.csv", name = "b", outdir = d, strategy = d .. "/mine.lua",
                 degree = 3, samples = 10, formats = { json = true } }
  local row = rc.section(spec)
  T.eq(row.status, "ok", row.error)
  T.eq(row.control_points, 10, "the file's strategy ran")
  spec.strategy, spec.open = "periodic", true
  row = rc.section(spec)
  T.eq(row.status, "ok", row.error)
  T.ok(slurp(d .. "/b.json"):find('"periodic": *false'), "an open curve")
  os.execute("rm -rf '" .. d .. "'")
end)

T.test("shard: the shards of any list partition it, balanced, indices kept", function()
  for n = 0, 30 do
    for N = 1, 7 do
      local seen, sizes = {}, {}
      for I = 0, N - 1 do
        local list = {}
        for k = 1, n do list[k] = { path = "p" .. k, name = "s" .. k } end
        local part = rc.shard(list, { index = I, count = N })
        sizes[#sizes + 1] = #part
        for _, inp in ipairs(part) do
          T.ok(not seen[inp.name], "in one shard only")
          seen[inp.name] = true
          T.eq(inp.name, "s" .. inp.index, "index = position in the whole list")
        end
      end
      local count = 0
      for _ in pairs(seen) do count = count + 1 end
      T.eq(count, n, "every input in some shard")
      T.ok(math.max(table.unpack(sizes)) - math.min(table.unpack(sizes)) <= 1, "balanced")
    end
  end
end)

T.test("user_message: Lua positions and argument wrappers off, paths and debug kept", function()
  T.eq(rc.user_message("/x/y/auto.lua:498: bad argument #1 to 'breaks' (5 points leave few spans)",
                       "a.csv"), "5 points leave few spans")
  T.eq(rc.user_message("a.csv:4: not a number: 'abc'", "a.csv"), "a.csv:4: not a number: 'abc'")
  T.ok(rc.user_message("mine.lua:1: attempt to index a nil value (local 't')", "a.csv")
       :find("^internal error %(attempt to index a nil value"), "a bug says it is one")
  T.eq(rc.user_message("boom\nstack traceback:\n\tx.lua:1", "a.csv"), "boom")
  local full = "mine.lua:1: boom\nstack traceback:\n\tmine.lua:1: in main chunk"
  T.eq(rc.user_message(full, "a.csv", true), full, "--debug keeps everything")
  T.eq(rc.failure_line { input = "a.csv", error = "a.csv:4: bad" }, "a.csv:4: bad", "path once")
  T.eq(rc.failure_line { input = "a.csv", error = "too few" }, "a.csv: too few")
end)

T.test("report.json_decode: reads what report.json writes, and standard JSON", function()
  local s = 12345
  local function rnd() s = (s * 1103515245 + 12345) % 2147483648; return s / 2147483648 end
  local function value(depth)
    local k = math.floor(rnd() * (depth > 3 and 4 or 6))
    if k == 0 then return (rnd() - 0.5) * 10 ^ math.floor(rnd() * 40 - 20) end
    if k == 1 then return math.floor(rnd() * 1e6) end
    if k == 2 then
      local t = {}
      for i = 1, math.floor(rnd() * 8) do t[i] = string.char(math.floor(rnd() * 255) + 1) end
      return table.concat(t)
    end
    if k == 3 then return rnd() < 0.5 end
    local t = {}
    for i = 1, math.floor(rnd() * 5) do
      if k == 4 then t[i] = value(depth + 1) else t["k" .. i] = value(depth + 1) end
    end
    return t
  end
  for _ = 1, 300 do
    local text = report.json(value(0))
    local v, err = report.json_decode(text)
    T.ok(err == nil, err)
    T.eq(report.json(v), text, "round trip")
  end
  local v = report.json_decode(' { "a" : [1, -0.5, 2.5e-3, 1E2, true, false, null],\n "b": "\\u00e9\\n\\/" } ')
  T.eq(v.a[1], 1); T.eq(v.a[2], -0.5); T.eq(v.a[3], 2.5e-3); T.eq(v.a[4], 100.0)
  T.eq(v.a[5], true); T.eq(v.a[6], false); T.eq(v.a[7], report.null); T.eq(#v.a, 7)
  T.eq(v.b, "é\n/")
  for _, bad in ipairs { "", "{", "[1,]", '{"a" 1}', '"abc', "nul", "[1] x", '{"a":1,}' } do
    local r, msg = report.json_decode(bad)
    T.ok(r == nil and msg:find("^JSON: .* at byte %d+$"), ("'%s' refused: %s"):format(bad, tostring(msg)))
  end
end)
