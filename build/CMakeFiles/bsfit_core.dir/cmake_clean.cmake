file(REMOVE_RECURSE
  "CMakeFiles/bsfit_core.dir/src/core/basis.c.o"
  "CMakeFiles/bsfit_core.dir/src/core/basis.c.o.d"
  "CMakeFiles/bsfit_core.dir/src/core/curve.c.o"
  "CMakeFiles/bsfit_core.dir/src/core/curve.c.o.d"
  "CMakeFiles/bsfit_core.dir/src/core/knots.c.o"
  "CMakeFiles/bsfit_core.dir/src/core/knots.c.o.d"
  "CMakeFiles/bsfit_core.dir/src/core/memory.c.o"
  "CMakeFiles/bsfit_core.dir/src/core/memory.c.o.d"
  "CMakeFiles/bsfit_core.dir/src/core/status.c.o"
  "CMakeFiles/bsfit_core.dir/src/core/status.c.o.d"
  "libbsfit_core.a"
  "libbsfit_core.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang C)
  include(CMakeFiles/bsfit_core.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
