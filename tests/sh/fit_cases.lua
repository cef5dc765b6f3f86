-- fit_cases.lua OUT.json: weighted least-squares fits made by bsfit's Fitter, written with
-- their inputs, for tests/sh/scipy_fit_check.py to redo independently (scipy's design
-- matrices and a dense least-squares solve). Data are generated here, deterministically.
local bs = require "bsfit"

local out_path = assert(arg[1], "usage: bsfit fit_cases.lua OUT.json")

-- a linear congruential generator: the same cases on every machine
local seed = 20261123
local function rand()
  seed = (seed * 1103515245 + 12345) % 2147483648
  return seed / 2147483648
end

-- m noisy points of a star-shaped closed curve (or an arc of it), dim 2 or 3; every
-- `dup`-th point repeated (a zero chord: two points, one parameter)
local function section(m, dim, closed, dup)
  local rows = {}
  local span = closed and 2 * math.pi or 4.0
  local k = 0
  while #rows < m do
    local t = span * k / m
    local r = 1 + 0.25 * math.cos(3 * t) + 0.01 * (rand() - 0.5)
    local row = {2 * r * math.cos(t), r * math.sin(t)}
    if dim == 3 then row[3] = 0.3 * math.sin(2 * t) + 0.01 * rand() end
    rows[#rows + 1] = row
    if dup and k % dup == 0 and #rows < m then rows[#rows + 1] = {table.unpack(row)} end
    k = k + 1
  end
  return bs.points.new(rows)
end

local function weights(m)
  local w = bs.vector.new(m)
  for i = 1, m do w:set(i, 0.1 + 9.9 * rand() ^ 2) end
  return w
end

local function numbers(v)
  local s = {}
  for i = 1, #v do s[i] = string.format("%.17g", v[i]) end
  return "[" .. table.concat(s, ",") .. "]"
end

local function rows(P)
  local s = {}
  for i = 1, #P do s[i] = numbers({P:get(i)}) end
  return "[" .. table.concat(s, ",") .. "]"
end

local function vector(v) return numbers(v:totable()) end

local cases = {}

-- fit one case and record everything the checker needs
local function record_one(name, settings, P, u, w)
  local F = bs.fitter(settings)
  local r = bs.vector.new(#P)
  local C, rep = F:fit(P, u, w, r)
  assert(C, rep)
  local tan = settings.tangent_start and numbers(settings.tangent_start) or "null"
  local tan1 = settings.tangent_end and numbers(settings.tangent_end) or "null"
  cases[#cases + 1] = string.format(
    '{"name":"%s","degree":%d,"periodic":%s,"fix_ends":%s,"tangent_start":%s,"tangent_end":%s,' ..
    '"u":%s,"points":%s,"w":%s,"knots":%s,"ctrl":%s,"residuals":%s,"rms":%.17g,"max":%.17g,' ..
    '"max_index":%d,"rcond":%.17g}',
    name, C:degree(), tostring(C:is_periodic()), tostring(settings.fix_ends or false), tan, tan1,
    vector(u), rows(P), vector(w), numbers(C:knots():values()), rows(C:control_points()),
    vector(r), rep.rms, rep.max, rep.max_index, rep.rcond)
  assert(rep.solver == settings.solver, rep.solver)
  return C
end

-- every case by both solvers: the same problem, the same minimum
local function record(name, settings, P, u, w)
  local C
  for _, solver in ipairs{"qr", "cholesky"} do
    settings.solver = solver
    C = record_one(name .. " [" .. solver .. "]", settings, P, u, w)
  end
  return C
end

-- open fits, every degree, averaging and uniform knots, 2D and 3D
for p = 1, 5 do
  for _, rule in ipairs{"averaging", "uniform"} do
    local dim = p % 2 == 0 and 3 or 2
    local P = section(240, dim, false, nil)
    record(string.format("open p=%d %s %dD", p, rule, dim),
           {degree = p, count = 10 + 4 * p, rule = rule}, P, bs.params(P, "chord"), weights(#P))
  end
end

-- periodic fits, every degree, both closed rules
for p = 1, 5 do
  for _, rule in ipairs{"periodic-averaging", "carvalho-closed"} do
    local P = section(200, 2, true, nil)
    record(string.format("periodic p=%d %s", p, rule),
           {degree = p, count = 12 + 3 * p, periodic = true, rule = rule}, P,
           bs.params(P, "chord", {closed = true}), weights(#P))
  end
end

-- the fewest control points a degree allows: one Bezier segment (open), a period of p+1
-- distinct control points (every unknown wraps), and a few more
for p = 1, 4 do
  local P = section(60, 2, false, nil)
  record(string.format("open p=%d, n=p+1", p), {degree = p, count = p + 1}, P,
         bs.params(P, "chord"), weights(#P))
  P = section(60, 2, true, nil)
  for extra = 1, 3 do
    record(string.format("periodic p=%d, N=p+%d", p, extra),
           {degree = p, count = p + extra, periodic = true}, P,
           bs.params(P, "chord", {closed = true}), weights(#P))
  end
end

-- coincident consecutive points (shared parameters), open and periodic, centripetal too
do
  local P = section(150, 2, false, 7)
  record("open duplicates", {degree = 3, count = 20}, P, bs.params(P, "centripetal"), weights(#P))
  P = section(150, 3, true, 5)
  record("periodic duplicates 3D", {degree = 3, count = 20, periodic = true}, P,
         bs.params(P, "chord", {closed = true}), weights(#P))
end

-- exact end constraints
do
  local P = section(180, 2, false, nil)
  local u = bs.params(P, "chord")
  record("open fix_ends p=3", {degree = 3, count = 16, fix_ends = true}, P, u, weights(#P))
  record("open fix_ends p=2", {degree = 2, count = 9, fix_ends = true}, P, u, weights(#P))
  record("open tangents p=3", {degree = 3, count = 16, tangent_start = {1.5, 4.0},
                               tangent_end = {-2.0, 3.0}}, P, u, weights(#P))
  record("open start tangent p=4", {degree = 4, count = 14, tangent_start = {0.5, 3.0}}, P, u,
         weights(#P))
end

-- fixed knots and unsorted points: the fit does not depend on the order of the points
do
  local P = section(160, 2, false, nil)
  local u = bs.params(P, "chord")
  local C = record("open sorted", {degree = 3, count = 15}, P, u, weights(#P))
  local n, rows_, us = #P, {}, bs.vector.new(#P)
  local perm = {}
  for i = 1, n do perm[i] = i end
  for i = n, 2, -1 do
    local j = 1 + math.floor(rand() * i)
    perm[i], perm[j] = perm[j], perm[i]
  end
  for i = 1, n do
    rows_[i] = {P:get(perm[i])}
    us:set(i, u:get(perm[i]))
  end
  record("open shuffled, fixed knots", {degree = 3, knots = C:knots()}, bs.points.new(rows_), us,
         weights(n))
end

-- fixed knots on a narrower interval than the parameters: the points beyond the ends are
-- fitted by the end spans' polynomials continued (as C:eval extrapolates)
do
  local P = section(120, 2, false, nil)
  local u = bs.params(P, "chord")
  local K = bs.knots.new{degree = 3, values = {0.1, 0.1, 0.1, 0.1, 0.3, 0.5, 0.7, 0.9, 0.9, 0.9, 0.9}}
  record("open, parameters beyond the knots", {degree = 3, knots = K}, P, u, weights(#P))
end

local f = assert(io.open(out_path, "w"))
f:write("[\n", table.concat(cases, ",\n"), "\n]\n")
f:close()
print(#cases .. " fits written to " .. out_path)
