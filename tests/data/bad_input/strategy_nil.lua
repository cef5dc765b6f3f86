return { run = function(P, o) return nil, "no fit for you", "ESINGULAR" end }
