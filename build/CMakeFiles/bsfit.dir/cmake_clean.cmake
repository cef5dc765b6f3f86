file(REMOVE_RECURSE
  "CMakeFiles/bsfit.dir/src/cli/main.c.o"
  "CMakeFiles/bsfit.dir/src/cli/main.c.o.d"
  "bsfit"
  "bsfit.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang C)
  include(CMakeFiles/bsfit.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
