-- lua/bsfit/cli/reconstruct.lua
-- `bsfit reconstruct`: fit a closed curve to every input section and write the
-- curve (JSON, optionally IGES), its samples (CSV), a picture (SVG), a summary
-- (summary.csv, summary.json), the timings (timing.csv) and an overview page
-- (index.html). A section that fails is reported and the others still run; the
-- exit code is 1 when any failed, 2 on a usage error.
--
-- Determinism: summary.csv, summary.json, index.html and every per-section file
-- depend only on the inputs and options, never on -j or on timing; milliseconds
-- go to timing.csv alone, so the outputs of -j 1 and -j N are byte-identical
-- except timing.csv.

local bs = require "bsfit"
local report = require "bsfit.report"
local svg = require "bsfit.svg"

local M = {}

M.usage = [[
usage: bsfit reconstruct [INPUT...] [options]
  INPUT            point files (CSV or whitespace text: x,y[,z][,w]); a directory
                   means every *.csv, *.txt, *.xy, *.xyz, *.dat, *.pts file in it.
                   No INPUT: the demo set ($BSFIT_DEMO_DIR or tests/data/demo).
  -o OUTDIR        output directory (default bsfit-out)
  --strategy S     auto | carvalho | periodic | FILE.lua (default auto)
  --degree P       curve degree (default 3)
  --count N|auto   control points (default auto: the paper's inversion / 50% rule);
                   more than the points allow is an error naming the limit
  --tol T          auto, periodic: add control points until the max deviation is <= T
                   (not met: the best fit, and a warning on stderr and in the summary)
  --open           fit open curves (auto and periodic strategies)
  --samples K      curve samples written to <name>.csv (default 1000)
  --format LIST    any of json,svg,csv,iges (default json,svg,csv)
  -j N             run N sections at a time, one Lua state per worker (default 1)
  -q               no progress line
  -h, --help       this text
]]

local clock = (bs.parallel and bs.parallel.clock) or os.clock

local function warn(fmt, ...)
  io.stderr:write("bsfit reconstruct: ", fmt:format(...), "\n")
end

-- {======================================================================
-- Arguments
-- =======================================================================

local function positive_integer(s, what)
  local n = math.tointeger(tonumber(s))
  if not n or n < 1 then error(("%s must be a positive integer, got '%s'"):format(what, tostring(s)), 0) end
  return n
end

local formats_known = { json = true, svg = true, csv = true, iges = true }

local function parse_formats(s)
  local f = {}
  for name in tostring(s):gmatch("[^,]+") do
    if not formats_known[name] then error(("unknown format '%s' (json, svg, csv, iges)"):format(name), 0) end
    f[name] = true
  end
  if next(f) == nil then error("--format needs at least one of json, svg, csv, iges", 0) end
  return f
end

-- Options of one option word: a function(o, value) and whether it takes a value.
local flags = {
  ["-o"] = function(o, v) o.outdir = v end,
  ["--strategy"] = function(o, v) o.strategy = v end,
  ["--degree"] = function(o, v)
    o.degree = positive_integer(v, "--degree")
    if o.degree > 30 then error("--degree must be at most 30 (BSFIT_MAX_DEGREE)", 0) end
  end,
  ["--count"] = function(o, v) o.count = v ~= "auto" and positive_integer(v, "--count") or nil end,
  ["--tol"] = function(o, v)
    o.tol = tonumber(v)
    if not o.tol or not (o.tol >= 0) then error("--tol must be a number >= 0, got '" .. v .. "'", 0) end
  end,
  ["--samples"] = function(o, v)
    o.samples = positive_integer(v, "--samples")
    if o.samples < 2 then error("--samples must be at least 2", 0) end
  end,
  ["--format"] = function(o, v) o.formats = parse_formats(v) end,
  ["-j"] = function(o, v) o.jobs = positive_integer(v, "-j") end,
}
local switches = {
  ["--open"] = function(o) o.open = true end,
  ["-q"] = function(o) o.quiet = true end,
  ["-h"] = function(o) o.help = true end,
  ["--help"] = function(o) o.help = true end,
}

-- Parses the argument list. Returns the options, or raises with a usage message.
function M.parse(args)
  local o = { inputs = {}, outdir = "bsfit-out", strategy = "auto", degree = 3,
              samples = 1000, formats = parse_formats("json,svg,csv"), jobs = 1 }
  local i = 1
  while i <= #args do
    local a = args[i]
    local name, value = a:match("^(%-%-[%w-]+)=(.*)$")
    name = name or a
    if flags[name] then
      if value == nil then
        i = i + 1
        value = args[i]
        if value == nil then error("option " .. name .. " needs a value", 0) end
      end
      flags[name](o, value)
    elseif switches[a] then
      switches[a](o)
    elseif a:sub(1, 1) == "-" and a ~= "-" then
      error("unknown option '" .. a .. "'", 0)
    else
      o.inputs[#o.inputs + 1] = a
    end
    i = i + 1
  end
  if o.tol and o.strategy == "carvalho" then error("--tol needs --strategy auto or periodic (or a FILE.lua)", 0) end
  if o.open and o.strategy == "carvalho" then error("--open needs --strategy auto or periodic (or a FILE.lua)", 0) end
  return o
end

-- }======================================================================

-- {======================================================================
-- Inputs
-- =======================================================================

-- True when path names a directory (bs.io.kind: stat, no shell).
local function is_dir(path) return bs.io.kind(path) == "directory" end

local point_ext = { csv = true, txt = true, xy = true, xyz = true, dat = true, pts = true }

-- The point files of a directory, sorted by name (bs.io.listdir: any byte a name may
-- hold, newlines included). Raises with the system's reason when it cannot be listed.
local function list_dir(dir)
  local names, err = bs.io.listdir(dir)
  if not names then error(err, 0) end
  local files, base = {}, dir:gsub("/+$", "") -- "/" becomes "": paths "/name"
  for _, name in ipairs(names) do
    local ext = name:match("%.([%w]+)$")
    local path = base .. "/" .. name
    if ext and point_ext[ext:lower()] and not is_dir(path) then files[#files + 1] = path end
  end
  return files
end

-- The directory holding the shipped lua/ modules (found through package.path).
local function lua_dir()
  local f = package.searchpath and package.searchpath("bsfit.cli.reconstruct", package.path)
  return f and f:gsub("/?bsfit/cli/reconstruct%.lua$", "")
end

-- Where the demo set is: $BSFIT_DEMO_DIR, else <luadir>/../tests/data/demo.
function M.demo_dir()
  local env = os.getenv("BSFIT_DEMO_DIR")
  if env and env ~= "" then return env end
  local d = lua_dir()
  if not d or d == "" or d == "." then return "../tests/data/demo" end
  local up = d:match("^(.*)/[^/]+$")
  return (up or ".") .. "/tests/data/demo"
end

-- The section name of a path: its last component without the extension.
local function section_name(p)
  local base = (p:gsub("/+$", ""):match("([^/]*)$") or ""):gsub("%.[^.]*$", "")
  base = base:gsub("[%c]", "_") -- a newline in a name would break the summary's lines
  return base ~= "" and base or "section"
end

-- Input sections: {path = ..., name = ...}, names made unique by a suffix. A path
-- that names nothing, or ends with '/' but is no directory, stays an input: its
-- section fails with the system's reason and the others still run. Raises when a
-- directory cannot be listed.
function M.inputs(list)
  local paths = {}
  if #list == 0 then list = { M.demo_dir() } end
  for _, a in ipairs(list) do
    if is_dir(a) then
      local files = list_dir(a)
      if #files == 0 then warn("%s: no point files in this directory", a) end
      for _, f in ipairs(files) do paths[#paths + 1] = f end
    else
      paths[#paths + 1] = a
    end
  end
  local seen, out = {}, {}
  for _, p in ipairs(paths) do
    local base = section_name(p)
    local name, k = base, 1
    while seen[name] do k = k + 1; name = base .. "_" .. k end
    seen[name] = true
    out[#out + 1] = { path = p, name = name }
  end
  return out
end

-- }======================================================================

-- {======================================================================
-- One section
-- =======================================================================

local strategies = {}

-- The strategy module: a built-in name or a FILE.lua returning the module.
local function load_strategy(s)
  if strategies[s] then return strategies[s] end
  local mod
  if s:find("/") or s:match("%.lua$") then
    local chunk, err = loadfile(s, "t")
    if not chunk then error("strategy " .. err, 0) end
    mod = chunk()
  else
    local ok, m = pcall(require, "bsfit.strategy." .. s)
    if not ok then error(("unknown strategy '%s' (auto, carvalho, periodic or FILE.lua)"):format(s), 0) end
    mod = m
  end
  if type(mod) ~= "table" or type(mod.run) ~= "function" then
    error("strategy " .. s .. " does not return a table with a run function", 0)
  end
  strategies[s] = mod
  return mod
end

-- Curve samples as Points: C:sample(k) when bound, else evaluation at k params.
local function samples(C, k)
  if C.sample then return C:sample(k) end
  local a, b = C:domain()
  local n = C:is_periodic() and k or k - 1
  local u = {}
  for i = 0, k - 1 do u[i + 1] = a + (b - a) * i / n end
  return C:eval_many(bs.vector.new(u))
end

local function points_csv(S)
  local dim, out = S:dim(), {}
  out[1] = dim == 3 and "x,y,z" or "x,y"
  for i = 1, #S do
    local t = { S:get(i) }
    for k = 1, #t do t[k] = report.num(t[k]) end
    out[i + 1] = table.concat(t, ",")
  end
  return table.concat(out, "\n") .. "\n"
end

local function control_table(C)
  local ctrl = C:control_points()
  if type(ctrl) ~= "table" then ctrl = ctrl:totable() end
  local N = C:distinct()
  local t = {}
  for i = 1, N do t[i] = ctrl[i] end
  return t
end

-- Writes the requested files of a fitted section.
local function write_outputs(spec, P, C, rep, S)
  local base = spec.outdir .. "/" .. spec.name
  local f = spec.formats
  if f.json then report.must_write(base .. ".json", C:to_json()) end
  if f.iges then
    local ok, err = C:write(base .. ".iges")
    if not ok then error("cannot write " .. base .. ".iges: " .. tostring(err), 0) end
  end
  if f.csv then report.must_write(base .. ".csv", points_csv(S)) end
  if f.svg then
    local markers = {}
    local sx, sy = P:get(rep.start_index or 1)
    markers[1] = { sx, sy, "start" }
    if rep.max_index then
      local wx, wy = P:get(rep.max_index)
      markers[2] = { wx, wy, ("max %.3g"):format(rep.max) }
    end
    report.must_write(base .. ".svg", svg.section {
      points = P, samples = S, control = control_table(C), closed = C:is_periodic(),
      markers = markers, title = spec.name })
  end
end

-- The strategy options a section's spec asks for.
local function strategy_opts(spec, w)
  local o = { degree = spec.degree }
  if spec.count then o.count = spec.count end
  if spec.tol then o.tol = spec.tol end
  if spec.open then o.closed = false end
  if w then o.point_weights = w end
  return o
end

-- A hint for a section that failed: coordinates so large that squared distances
-- overflow a double (every strategy measures them) fail deep inside a step with a
-- message about that step. Looked at only after a failure (one C pass over P).
local function magnitude_hint(P)
  local v = bs.vector.frombytes(P:bytes())
  local big = math.max(math.abs(v:max()), math.abs(v:min()))
  if big > 1e150 then
    return (" (coordinates up to %.3g: too large to square in double precision; scale the section)")
      :format(big)
  end
  return ""
end

-- A strategy's refusal as a user reads it: a binding's argument error raised inside a
-- shipped module ("…/bsfit/strategy/auto.lua:174: bad argument #1 to 'breaks' (40
-- points leave too few knot spans for degree 20)") is the section not suiting the
-- strategy: its reason, without the module's file:line and the argument number.
-- Anything else (a bug: "attempt to index a nil value") is kept whole.
local function user_message(strategy, err)
  err = tostring(err)
  local reason = err:match("^[^\n]-/bsfit/[%w_/]+%.lua:%d+: bad argument #%d+ to '[^']*' %((.*)%)$")
  if reason then return ("%s: %s"):format(strategy, reason) end
  return err
end

-- Fits one section and writes its files. spec: path, name, outdir, strategy,
-- degree, count, tol, open, samples, formats. Never raises: returns the summary
-- row, with status "error" and the message when something failed.
function M.section(spec)
  local t0 = clock()
  local row = { name = spec.name, input = spec.path, status = "ok", error = "" }
  local ok, err = pcall(function()
    local P, w = bs.points.read(spec.path)
    if not P then error(tostring(w), 0) end
    row.points = #P
    local okr, C, rep = pcall(load_strategy(spec.strategy).run, P, strategy_opts(spec, w))
    if not okr then error(user_message(spec.strategy, C) .. magnitude_hint(P), 0) end
    if not C then error(tostring(rep) .. magnitude_hint(P), 0) end
    row.control_points = C:distinct()
    row.rms, row.max, row.max_index = rep.rms, rep.max, rep.max_index
    row.max_trusted = rep.max_trusted -- set when the file down-weights some points
    row.start_index = rep.start_index
    -- what the strategy could not honour or changed (rep.warnings): one field, "; "-joined
    row.warnings = table.concat(rep.warnings or {}, "; "):gsub("[%c]", " ")
    write_outputs(spec, P, C, rep, samples(C, spec.samples))
  end)
  if not ok then
    row.status, row.error = "error", tostring(err):gsub("\n.*", "")
  end
  row.ms = (clock() - t0) * 1000
  return row
end

-- The worker entry of -j: a serialized spec in, a serialized row out.
function M.section_serialized(s)
  return report.serialize(M.section(report.deserialize(s)))
end

-- }======================================================================

-- {======================================================================
-- The job
-- =======================================================================

local summary_columns = { "name", "input", "points", "control_points", "rms", "max", "max_index",
                          "max_trusted", "start_index", "status", "error", "warnings" }

local function specs_of(o, inputs)
  local specs = {}
  for i, inp in ipairs(inputs) do
    specs[i] = { path = inp.path, name = inp.name, outdir = o.outdir, strategy = o.strategy,
                 degree = o.degree, count = o.count, tol = o.tol, open = o.open,
                 samples = o.samples, formats = o.formats }
  end
  return specs
end

-- Runs the sections one after the other, with a progress line on a terminal.
local function run_serial(specs, progress)
  local rows = {}
  for i, s in ipairs(specs) do
    if progress then io.stderr:write(("\r[%d/%d] %s\027[K"):format(i, #specs, s.name)) end
    rows[i] = M.section(s)
  end
  if progress and #specs > 0 then io.stderr:write("\r\027[K") end
  return rows
end

-- Runs the sections on n worker threads (bs.parallel.map), rows in input order.
local function run_parallel(specs, n)
  local items = {}
  for i, s in ipairs(specs) do items[i] = report.serialize(s) end
  local res, errs = bs.parallel.map("bsfit.cli.reconstruct", "section_serialized", items, n)
  local rows = {}
  for i, s in ipairs(specs) do
    if res[i] then
      rows[i] = report.deserialize(res[i])
    else
      rows[i] = { name = s.name, input = s.path, status = "error", ms = 0,
                  error = "worker: " .. tostring(errs and errs[i] or "no result"):gsub("\n.*", "") }
    end
  end
  return rows
end

local function is_terminal()
  local ok = os.execute("test -t 2")
  return ok == true or ok == 0
end

local function write_summaries(o, rows)
  report.must_write(o.outdir .. "/summary.csv", report.csv(summary_columns, rows))
  local clean = {}
  for i, r in ipairs(rows) do
    local c = {}
    for _, k in ipairs(summary_columns) do c[k] = r[k] end
    clean[i] = c
  end
  report.must_write(o.outdir .. "/summary.json", report.json {
    strategy = o.strategy, degree = o.degree, sections = clean } .. "\n")
  local timing = {}
  for i, r in ipairs(rows) do timing[i] = { name = r.name, ms = ("%.3f"):format(r.ms or 0) } end
  report.must_write(o.outdir .. "/timing.csv", report.csv({ "name", "ms" }, timing))
  local items = {}
  for i, r in ipairs(rows) do
    items[i] = { name = r.name, svg = (o.formats.svg and r.status == "ok") and (r.name .. ".svg") or nil,
                 caption = r.status == "ok" and ("%s: %d points, %d control points, max %.3g")
                   :format(r.name, r.points, r.control_points, r.max) or (r.name .. ": " .. r.error) }
  end
  report.must_write(o.outdir .. "/index.html", svg.index("bsfit reconstruct", items))
end

-- Entry point: args is the list of command-line words after `reconstruct`.
-- Returns the exit code.
function M.main(args)
  local okp, o = pcall(M.parse, args or {})
  if not okp then
    warn("%s", tostring(o))
    io.stderr:write(M.usage)
    return 2
  end
  if o.help then io.stdout:write(M.usage); return 0 end
  local okl, lerr = pcall(load_strategy, o.strategy)
  if not okl then warn("%s", tostring(lerr)); return 2 end
  local oki, inputs = pcall(M.inputs, o.inputs)
  if not oki then warn("%s", tostring(inputs)); return 2 end
  if #inputs == 0 then warn("no input sections"); return 2 end
  local okd, derr = bs.io.mkdir(o.outdir)
  if not okd then warn("%s", tostring(derr)); return 2 end
  local specs = specs_of(o, inputs)
  local rows
  if o.jobs > 1 and #specs > 1 and bs.parallel then
    rows = run_parallel(specs, o.jobs)
  else
    if o.jobs > 1 and not bs.parallel then warn("-j: this build has no bsfit.parallel; running serially") end
    rows = run_serial(specs, not o.quiet and is_terminal())
  end
  local failed = 0
  for _, r in ipairs(rows) do
    if r.status ~= "ok" then
      failed = failed + 1
      -- the reader's messages start with the path already
      if r.error:sub(1, #r.input + 1) == r.input .. ":" then warn("%s", r.error)
      else warn("%s: %s", r.input, r.error) end
    elseif r.warnings and r.warnings ~= "" then
      warn("%s: warning: %s", r.input, r.warnings)
    end
  end
  local okw, werr = pcall(write_summaries, o, rows)
  if not okw then warn("%s", tostring(werr)); return 1 end
  if not o.quiet then
    io.stderr:write(("bsfit reconstruct: %d sections, %d failed, results in %s\n")
                    :format(#rows, failed, o.outdir))
  end
  return failed > 0 and 1 or 0
end

return M
