-- lua/bsfit/progress.lua
-- What a batch says while it runs (docs/batch.md): a progress line on a terminal
-- (sections done / total, failures so far, rate, time left), rewritten in place with
-- "\r"; each failure on its own line as it happens, whether or not stderr is a
-- terminal; and the final line.
--
--   local progress = require "bsfit.progress"
--   local p = progress.new{total = 40, live = true, out = io.stderr,
--                          prefix = "bsfit reconstruct: "}
--   p:ended(ok, line)           -- once per section, as it ends (line: failure, warnings)
--   p:finish()                  -- clears the line

local M = {}

local P = {}
P.__index = P

-- o.total, o.live (draw the progress line), o.out (a file, io.stderr), o.prefix,
-- o.clock (a function returning seconds).
function M.new(o)
  local p = setmetatable({ total = o.total, live = o.live, out = o.out or io.stderr,
                           prefix = o.prefix or "", clock = o.clock or os.clock,
                           done = 0, failed = 0, shown = false }, P)
  p.t0 = p.clock()
  if p.live then p:draw() end
  return p
end

-- The progress line's text: "[12/40] 30%, 1 failed, 3.2 sections/s, 9 s left".
function P:line()
  local t = math.max(self.clock() - self.t0, 1e-9)
  local rate = self.done / t
  local parts = { ("[%d/%d] %d%%"):format(self.done, self.total,
                                         self.total > 0 and self.done * 100 // self.total or 100) }
  parts[#parts + 1] = ("%d failed"):format(self.failed)
  if self.done > 0 then
    parts[#parts + 1] = ("%.3g sections/s"):format(rate)
    parts[#parts + 1] = ("%.0f s left"):format((self.total - self.done) / rate)
  end
  return self.prefix .. table.concat(parts, ", ")
end

function P:draw()
  self.out:write("\r", self:line(), "\027[K")
  self.out:flush()
  self.shown = true
end

function P:clear()
  if self.shown then self.out:write("\r\027[K"); self.shown = false end
end

-- One section ended (ok: it succeeded); line: what to say about it on its own line
-- (its failure, its warnings), or nil.
function P:ended(ok, line)
  self.done = self.done + 1
  if not ok then self.failed = self.failed + 1 end
  if line then
    self:clear()
    self.out:write(self.prefix, line, "\n")
    self.out:flush()
  end
  if self.live then self:draw() end
end

function P:finish()
  self:clear()
  self.out:flush()
end

-- Seconds since the start.
function P:elapsed() return self.clock() - self.t0 end

return M
