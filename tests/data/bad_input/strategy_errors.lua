return { run = function(P, o) error("strategy refused the section", 0) end }
