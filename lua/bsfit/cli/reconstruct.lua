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
local progress = require "bsfit.progress"
local section_output = require "bsfit.section_output"
local options = require "bsfit.cli_options"

local M = {}

M.usage = [[
usage: bsfit reconstruct [INPUT...] [options]
  INPUT            point files (CSV or whitespace text: x,y[,z][,w]); a directory
                   means every *.csv, *.txt, *.xy, *.xyz, *.dat, *.pts file in it.
                   No INPUT: the demo set ($BSFIT_DEMO_DIR, else the shipped one).
  -o OUTDIR        output directory (default bsfit-out)
  --strategy S     auto | carvalho | periodic | FILE.lua (default auto)
  --degree P       curve degree (default 3)
  --count N|auto   control points (default auto: the paper's inversion / 50% rule);
                   more than the points allow is an error naming the limit
  --tol T          auto, periodic: add control points until the max deviation is <= T
                   (not met: the best fit, and a warning on stderr and in the summary)
  --open           fit open curves (auto and periodic strategies)
  --closed         fit closed curves (auto decides from the data when neither is given)
  --smooth-tol T   then smooth each curve as much as possible within distance T
                   (kernel filters, result cubic: docs/filtering.md)
  --samples K      curve samples written to <name>.csv (default 1000)
  --format LIST    any of json,svg,csv,iges,step,dxf (default json,svg,csv)
  --polygon MODE   the control polygon in the pictures: auto (drawn up to 60
                   control points), on, off (default auto)
  -j N             run N sections at a time, one Lua state per worker (default 1)
  --shard I/N      process only shard I of N (0 <= I < N): the inputs at positions
                   I+1, I+1+N, ... of the sorted input list; `bsfit merge` joins them
  -q               no progress line and no final line (failures are still reported)
  --debug          failures with the Lua traceback
  -h, --help       this text
]]

local clock = (bs.parallel and bs.parallel.clock) or os.clock

local function warn(fmt, ...)
  io.stderr:write("bsfit reconstruct: ", fmt:format(...), "\n")
end

-- {======================================================================
-- Arguments
-- =======================================================================

local positive_integer = options.positive_integer

local formats_known = { "json", "svg", "csv", "iges", "step", "dxf" }

local function parse_formats(s) return options.formats(s, formats_known) end

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
  ["--smooth-tol"] = function(o, v)
    o.smooth_tol = tonumber(v)
    if not (o.smooth_tol and o.smooth_tol > 0 and o.smooth_tol < math.huge) then
      error("--smooth-tol must be a number > 0, got '" .. v .. "'", 0)
    end
  end,
  ["--samples"] = function(o, v)
    o.samples = positive_integer(v, "--samples")
    if o.samples < 2 then error("--samples must be at least 2", 0) end
  end,
  ["--format"] = function(o, v) o.formats = parse_formats(v) end,
  ["-j"] = function(o, v) o.jobs = positive_integer(v, "-j") end,
  ["--shard"] = function(o, v)
    local i, n = tostring(v):match("^(%d+)/(%d+)$")
    i, n = math.tointeger(tonumber(i)), math.tointeger(tonumber(n))
    if not i or not n or n < 1 or i >= n then
      error(("--shard must be I/N with 0 <= I < N, got '%s'"):format(tostring(v)), 0)
    end
    o.shard = { index = i, count = n }
  end,
  ["--polygon"] = function(o, v)
    local modes = { auto = "auto", on = true, off = false }
    if modes[v] == nil then error("--polygon must be auto, on or off, got '" .. v .. "'", 0) end
    if modes[v] == "auto" then o.polygon = nil else o.polygon = modes[v] end
  end,
}
local switches = {
  ["--open"] = function(o) o.open = true end,
  ["--closed"] = function(o) o.closed = true end,
  ["-q"] = function(o) o.quiet = true end,
  ["--debug"] = function(o) o.debug = true end,
  ["-h"] = function(o) o.help = true end,
  ["--help"] = function(o) o.help = true end,
}

-- Parses the argument list. Returns the options, or raises with a usage message.
function M.parse(args)
  local o = { inputs = {}, outdir = "bsfit-out", strategy = "auto", degree = 3,
              samples = 1000, formats = parse_formats("json,svg,csv"), jobs = 1 }
  options.parse(args, o, flags, switches, function(_, a) o.inputs[#o.inputs + 1] = a end)
  if o.tol and o.strategy == "carvalho" then error("--tol needs --strategy auto or periodic (or a FILE.lua)", 0) end
  if o.open and o.strategy == "carvalho" then error("--open needs --strategy auto or periodic (or a FILE.lua)", 0) end
  if o.open and o.closed then error("--open and --closed contradict each other", 0) end
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

-- Where the demo set is: $BSFIT_DEMO_DIR, else <luadir>/../tests/data/demo (a source
-- tree), else <luadir>/../../bsfit/demo (installed: P/share/lua/5.4 -> P/share/bsfit/demo).
function M.demo_dir()
  local env = os.getenv("BSFIT_DEMO_DIR")
  if env and env ~= "" then return env end
  local d = lua_dir()
  if not d or d == "" or d == "." then return "../tests/data/demo" end
  local up = d:match("^(.*)/[^/]+$") or "."
  local installed = (up:match("^(.*)/[^/]+$") or ".") .. "/bsfit/demo"
  if not is_dir(up .. "/tests/data/demo") and is_dir(installed) then return installed end
  return up .. "/tests/data/demo"
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

-- loading strategies, curve samples and a section's files: shared with `bsfit cloud`
local load_strategy = section_output.load_strategy
local samples = section_output.samples
local write_outputs = section_output.write_outputs

-- The strategy options a section's spec asks for.
local function strategy_opts(spec, w)
  local o = { degree = spec.degree }
  if spec.count then o.count = spec.count end
  if spec.tol then o.tol = spec.tol end
  if spec.open then o.closed = false end
  if spec.closed and spec.strategy ~= "carvalho" then o.closed = true end -- carvalho: always closed
  if spec.smooth_tol then o.smooth = { tol = spec.smooth_tol } end
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
  local row = { name = spec.name, input = spec.path, status = "ok", error = "", index = spec.index }
  local ok, err = xpcall(function()
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
    row.warnings = M.warnings_text(rep.warnings)
    -- open or closed as fitted (auto decides from the data), and self-intersections
    if rep.closed ~= nil then row.closed = rep.closed else row.closed = C:is_periodic() end
    row.closed = row.closed and "yes" or "no"
    row.crossings = rep.crossings
    write_outputs(spec, P, C, rep, samples(C, spec.samples), w)
  end, spec.debug and debug.traceback or function(e) return e end)
  if not ok then
    row.status, row.error = "error", M.user_message(err, spec.path, spec.debug)
  end
  row.ms = (clock() - t0) * 1000
  return row
end

-- A strategy's warnings (a string or an array of strings) as one line.
function M.warnings_text(w)
  if type(w) == "table" then
    local t = {}
    for i, s in ipairs(w) do t[i] = tostring(s) end
    w = table.concat(t, "; ")
  end
  return w and tostring(w):gsub("%s*\n%s*", " ") or ""
end

-- The message a user sees for a failed section: one line, without Lua's
-- "file.lua:123:" positions and traceback (unless debug: then the whole traceback).
function M.user_message(err, path, debug_on)
  local msg = tostring(err)
  if debug_on then return msg end
  msg = msg:gsub("\nstack traceback:.*", ""):gsub("\n.*", "")
  if msg:sub(1, #path + 1) == path .. ":" then return msg end -- the reader's "file:line: ..."
  local internal = false
  repeat -- positions of Lua code: "[string ...]:12: ", "/x/y/auto.lua:498: "
    local stripped = msg:gsub("^[^%s:]*%.lua:%d+:%s*", ""):gsub('^%[string "[^"]*"%]:%d+:%s*', "")
    if stripped ~= msg then internal = true end
    local done = stripped == msg
    msg = stripped
  until done
  -- "bad argument #1 to 'breaks' (5 points leave too few ...)": the reason alone
  msg = msg:match("^bad argument #%d+ to '[^']*' %((.*)%)$") or msg
  if internal and msg:match("^attempt to") then
    msg = "internal error (" .. msg .. "); rerun with --debug for the details"
  end
  return msg
end

-- The line that reports a failed section: its path once, then the message.
function M.failure_line(row)
  local msg, path = tostring(row.error), tostring(row.input)
  if msg:sub(1, #path + 1) == path .. ":" then return msg end
  return path .. ": " .. msg
end

-- What a section's end says on stderr: the failure line, "PATH: warning: ..." for a
-- section with warnings, nil otherwise.
function M.report_line(row)
  if row.status ~= "ok" then return M.failure_line(row) end
  if row.warnings and row.warnings ~= "" then
    return ("%s: warning: %s"):format(tostring(row.input), row.warnings)
  end
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
                          "max_trusted", "start_index", "status", "error", "warnings", "closed",
                          "crossings", "index" }
M.summary_columns = summary_columns

local function specs_of(o, inputs)
  local specs = {}
  for i, inp in ipairs(inputs) do
    specs[i] = { path = inp.path, name = inp.name, index = inp.index, outdir = o.outdir,
                 strategy = o.strategy, degree = o.degree, count = o.count, tol = o.tol,
                 open = o.open, closed = o.closed, samples = o.samples, formats = o.formats,
                 polygon = o.polygon, smooth_tol = o.smooth_tol,
                 debug = o.debug }
  end
  return specs
end

-- Runs the sections one after the other; prog hears of each as it ends.
local function run_serial(specs, prog)
  local rows = {}
  for i, s in ipairs(specs) do
    rows[i] = M.section(s)
    prog:ended(rows[i].status == "ok", M.report_line(rows[i]))
  end
  return rows
end

-- The row of a section whose worker failed outside M.section (its engine could not
-- start, or ran out of memory).
local function worker_failed(s, err, debug_on)
  return { name = s.name, input = s.path, index = s.index, status = "error", ms = 0,
           error = "worker: " .. M.user_message(err or "no result", s.path, debug_on) }
end

-- Runs the sections on n worker threads (bs.parallel.map), rows in input order; prog
-- hears of each section as it ends, whatever its place.
local function run_parallel(specs, n, prog, debug_on)
  local items, rows = {}, {}
  for i, s in ipairs(specs) do items[i] = report.serialize(s) end
  local function done(i, ok, out)
    rows[i] = ok and report.deserialize(out) or worker_failed(specs[i], out, debug_on)
    prog:ended(rows[i].status == "ok", M.report_line(rows[i]))
  end
  bs.parallel.map("bsfit.cli.reconstruct", "section_serialized", items,
                  { threads = n, done = done })
  for i, s in ipairs(specs) do rows[i] = rows[i] or worker_failed(s, nil, debug_on) end
  return rows
end

local function is_terminal()
  local ok = os.execute("test -t 2")
  return ok == true or ok == 0
end

local function exists(path)
  local f = io.open(path, "rb")
  if f then f:close() end
  return f ~= nil
end

-- Writes summary.csv, summary.json, timing.csv and index.html of the rows (in input
-- order) into outdir. meta: strategy, degree, and shard ({index, count, total}: a
-- shard's summary.json says which one it is, so `bsfit merge` can tell a missing one).
-- Shared with `bsfit merge`, so a merged set of shards gives the same files as one run.
function M.write_summaries(outdir, meta, rows)
  report.must_write(outdir .. "/summary.csv", report.csv(summary_columns, rows))
  local clean = {}
  for i, r in ipairs(rows) do
    local c = {}
    for _, k in ipairs(summary_columns) do c[k] = r[k] end
    clean[i] = c
  end
  report.must_write(outdir .. "/summary.json", report.json {
    strategy = meta.strategy, degree = meta.degree, sections = clean, shard = meta.shard } .. "\n")
  local timing = {}
  for i, r in ipairs(rows) do timing[i] = { name = r.name, ms = ("%.3f"):format(r.ms or 0) } end
  report.must_write(outdir .. "/timing.csv", report.csv({ "name", "ms" }, timing))
  local items = {}
  for i, r in ipairs(rows) do
    local pic = r.name .. ".svg"
    local drawn = r.status == "ok" and exists(outdir .. "/" .. pic)
    items[i] = setmetatable({ svg = drawn and pic or nil }, { __index = r })
  end
  report.must_write(outdir .. "/index.html", svg.index("bsfit reconstruct", items))
end

-- The inputs of shard I/N: those at 1-based positions k with (k - 1) % N == I (round
-- robin over the sorted input list, so shards get similar mixes); each keeps its
-- position in the whole list as its index.
function M.shard(inputs, shard)
  local out = {}
  for k, inp in ipairs(inputs) do
    inp.index = k
    if not shard or (k - 1) % shard.count == shard.index then out[#out + 1] = inp end
  end
  return out
end

-- Runs the sections, with progress and failures on stderr; returns the rows.
local function run(o, specs)
  local prog = progress.new { total = #specs, live = not o.quiet and is_terminal(),
                              prefix = "bsfit reconstruct: ", clock = clock }
  local rows
  if o.jobs > 1 and #specs > 1 and bs.parallel then
    rows = run_parallel(specs, o.jobs, prog, o.debug)
  else
    if o.jobs > 1 and not bs.parallel then
      warn("-j: this build has no bsfit.parallel; running serially")
    end
    rows = run_serial(specs, prog)
  end
  prog:finish()
  return rows, prog:elapsed()
end

-- "N sections: K ok, F failed, W with warnings, in T s; outputs in DIR"
local function final_line(o, rows, seconds)
  local failed, warned = 0, 0
  for _, r in ipairs(rows) do
    if r.status ~= "ok" then failed = failed + 1
    elseif r.warnings and r.warnings ~= "" then warned = warned + 1 end
  end
  return failed, ("%s%d sections: %d ok, %d failed, %d with warnings, in %.1f s; outputs in %s")
    :format(o.shard and ("shard %d/%d: "):format(o.shard.index, o.shard.count) or "", #rows,
            #rows - failed, failed, warned, seconds, o.outdir)
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
  local oki, all = pcall(M.inputs, o.inputs)
  if not oki then warn("%s", tostring(all)); return 2 end
  local inputs = M.shard(all, o.shard)
  if o.shard then o.shard.total = #all end
  if #inputs == 0 and not o.shard then warn("no input sections"); return 2 end
  local okd, derr = bs.io.mkdir(o.outdir)
  if not okd then warn("%s", tostring(derr)); return 2 end
  local rows, seconds = run(o, specs_of(o, inputs))
  local okw, werr = pcall(M.write_summaries, o.outdir, o, rows)
  if not okw then warn("%s", tostring(werr)); return 1 end
  local failed, line = final_line(o, rows, seconds)
  if not o.quiet then warn("%s", line) end
  return failed > 0 and 1 or 0
end

return M
