local function f() error("boom in the script") end
f()
