local P = bs.points.new{{0,0},{1,0},{1,1},{0,1},{0.5,1.5}}
local C, rep = require('bsfit.strategy.periodic').run(P, {})
return rep.max