-- lua/bsfit/cli/merge.lua
-- `bsfit merge OUT DIR1 DIR2...`: joins the output directories of the shards of one
-- job (`bsfit reconstruct --shard I/N`, docs/batch.md) into OUT: the per-section files
-- are copied, and summary.csv, summary.json, timing.csv and index.html are written from
-- the shards' summaries, in the order of the whole input list (each row's index), so
-- they are byte for byte those of a single run of the same job (timing.csv aside: its
-- numbers are measured). Exit status: 0 merged, 1 a directory could not be read or the
-- shards do not belong together, 2 usage error.

local bs = require "bsfit"
local report = require "bsfit.report"
local rc = require "bsfit.cli.reconstruct"

local M = {}

M.usage = [[
usage: bsfit merge OUT DIR1 [DIR2 ...]
  OUT         the merged output directory (created; may be one of the DIRs)
  DIR...      output directories of `bsfit reconstruct --shard I/N` (or any runs of
              the same strategy and degree on different sections)
  -h, --help  this text
]]

-- Files of a run directory that merge writes itself rather than copies.
local generated = { ["summary.csv"] = true, ["summary.json"] = true, ["timing.csv"] = true,
                    ["index.html"] = true }


local function slurp(path)
  local f, err = io.open(path, "rb")
  if not f then return nil, err end
  local s = f:read("a")
  f:close()
  return s
end

-- The summary of one run directory: {strategy, degree, sections}, or raises.
local function read_summary(dir)
  local text, err = slurp(dir .. "/summary.json")
  if not text then error(("%s: no summary.json (%s)"):format(dir, tostring(err)), 0) end
  local s, jerr = report.json_decode(text)
  if type(s) ~= "table" or type(s.sections) ~= "table" then
    local why = tostring(jerr or "no sections")
    error(("%s/summary.json: not a bsfit summary (%s)"):format(dir, why), 0)
  end
  return s
end

-- name -> milliseconds of a run's timing.csv (absent or unreadable: none).
local function read_timing(dir)
  local t, text = {}, slurp(dir .. "/timing.csv")
  for line in (text or ""):gmatch("[^\n]+") do
    local name, ms = line:match('^"?(.-)"?,([%d.]+)$')
    if name and ms then t[name:gsub('""', '"')] = tonumber(ms) end
  end
  return t
end

-- Copies the per-section files of dir into out (not the generated ones).
-- (Listed in C, not through a shell: any name, a newline in it too.)
local function copy_files(dir, out)
  local names, err = bs.io.listdir(dir)
  if not names then error(err, 0) end
  for _, name in ipairs(names) do
    if not generated[name] and not name:match("%.tmp$") and bs.io.kind(dir .. "/" .. name) == "file" then
      local data = slurp(dir .. "/" .. name)
      if data then report.must_write(out .. "/" .. name, data) end
    end
  end
end

-- Raises unless the shards' summaries (array of {dir, shard}) are shards of one job,
-- and, given their rows, every shard once and the whole input list (1..total).
local function check_shards(shards, rows)
  local count, total, have = shards[1].shard.count, shards[1].shard.total, {}
  for _, s in ipairs(shards) do
    local sh = s.shard
    if sh.count ~= count or sh.total ~= total then
      error(("%s is shard %d/%d of %d inputs; %s of %d/%d of %d inputs: not one job")
        :format(s.dir, sh.index, sh.count, sh.total, shards[1].dir, shards[1].shard.index, count,
                total), 0)
    end
    if have[sh.index] and have[sh.index] ~= s.dir then
      error(("shard %d/%d is in both %s and %s"):format(sh.index, count, have[sh.index], s.dir), 0)
    end
    have[sh.index] = s.dir
  end
  if rows == nil then return end
  for i = 0, count - 1 do
    if not have[i] then
      error(("shard %d/%d is missing (no directory holds it)"):format(i, count), 0)
    end
  end
  if #rows ~= total then
    error(("%d sections in the shards, %d inputs in the job"):format(#rows, total), 0)
  end
end

-- The rows of every directory, in input order; raises when they do not fit together.
function M.rows(dirs)
  local sums, shards = {}, {}
  for k, dir in ipairs(dirs) do
    sums[k] = read_summary(dir)
    if type(sums[k].shard) == "table" then
      shards[#shards + 1] = { dir = dir, shard = sums[k].shard }
    end
  end
  if #shards > 0 and #shards < #dirs then
    error("some directories are shards, others are not", 0)
  end
  local rows, by_name, meta = {}, {}, { strategy = sums[1].strategy, degree = sums[1].degree }
  for k, dir in ipairs(dirs) do
    local s = sums[k]
    if s.strategy ~= meta.strategy or s.degree ~= meta.degree then
      error(("%s was made with strategy %s, degree %s; %s with strategy %s, degree %s")
        :format(dir, tostring(s.strategy), tostring(s.degree), dirs[1], tostring(meta.strategy),
                tostring(meta.degree)), 0)
    end
    if #shards > 0 then check_shards({ shards[1], shards[k] }, nil) end
    local timing = read_timing(dir)
    for _, r in ipairs(s.sections) do
      if by_name[r.name] then
        error(("section %s is in both %s and %s"):format(r.name, by_name[r.name], dir), 0)
      end
      by_name[r.name] = dir
      r.ms = timing[r.name]
      rows[#rows + 1] = r
    end
  end
  if #shards > 0 then check_shards(shards, rows) end
  table.sort(rows, function(a, b)
    local ia, ib = tonumber(a.index) or math.huge, tonumber(b.index) or math.huge
    if ia ~= ib then return ia < ib end
    return a.name < b.name
  end)
  return rows, meta
end

function M.main(args)
  if args[1] == "-h" or args[1] == "--help" then io.stdout:write(M.usage); return 0 end
  for _, a in ipairs(args) do
    if a:sub(1, 1) == "-" then
      io.stderr:write("bsfit merge: unknown option '", a, "'\n", M.usage)
      return 2
    end
  end
  if #args < 2 then
    io.stderr:write("bsfit merge: need OUT and at least one DIR\n", M.usage)
    return 2
  end
  local out, dirs = args[1], table.move(args, 2, #args, 1, {})
  local ok, err = pcall(function()
    local rows, meta = M.rows(dirs)
    assert(bs.io.mkdir(out))
    for _, dir in ipairs(dirs) do
      if dir:gsub("/+$", "") ~= out:gsub("/+$", "") then copy_files(dir, out) end
    end
    rc.write_summaries(out, meta, rows)
    io.stderr:write(("bsfit merge: %d sections from %d directories; outputs in %s\n")
                    :format(#rows, #dirs, out))
  end)
  if not ok then
    io.stderr:write("bsfit merge: ", tostring(err), "\n")
    return 1
  end
  return 0
end

return M
