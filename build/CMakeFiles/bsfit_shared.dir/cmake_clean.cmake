file(REMOVE_RECURSE
  "CMakeFiles/bsfit_shared.dir/src/core/basis.c.o"
  "CMakeFiles/bsfit_shared.dir/src/core/basis.c.o.d"
  "CMakeFiles/bsfit_shared.dir/src/core/curve.c.o"
  "CMakeFiles/bsfit_shared.dir/src/core/curve.c.o.d"
  "CMakeFiles/bsfit_shared.dir/src/core/knots.c.o"
  "CMakeFiles/bsfit_shared.dir/src/core/knots.c.o.d"
  "CMakeFiles/bsfit_shared.dir/src/core/memory.c.o"
  "CMakeFiles/bsfit_shared.dir/src/core/memory.c.o.d"
  "CMakeFiles/bsfit_shared.dir/src/core/status.c.o"
  "CMakeFiles/bsfit_shared.dir/src/core/status.c.o.d"
  "libbsfit.pdb"
  "libbsfit.so"
  "libbsfit.so.0"
  "libbsfit.so.0.1.0"
)

# Per-language clean rules from dependency scanning.
foreach(lang C)
  include(CMakeFiles/bsfit_shared.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
