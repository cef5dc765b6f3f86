return { run = function(P, o) return end
