local u = bs.params(bs.points.new{{0,0},{1,1},{2,0},{3,1},{4,0},{5,2}}, 'chord')
local F = bs.fitter{degree = 2, count = 4, solver = 'qr'}
return F:fit(bs.points.new{{0,0},{1,1},{2,0},{3,1},{4,0},{5,2}}, u)