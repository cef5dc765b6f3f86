local C = bs.curve.new{degree = 3, knots = {0,0,0,0,1,2,2,2,2}, control_points = {{0,0},{1,2},{2,0},{3,1},{4,0}}}
local D = C:elevate(1):insert(0.5, 2):reverse()
return D:eval(0.3), C:length(), bs.filter.box(C, {delta = 0.1})