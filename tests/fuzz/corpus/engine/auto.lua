local t = {} for i = 1, 100 do t[i] = {math.cos(i), math.sin(i)} end
return require('bsfit.strategy.auto').run(bs.points.new(t), {count = 8})