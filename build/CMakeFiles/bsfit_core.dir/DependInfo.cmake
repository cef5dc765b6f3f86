
# Consider dependencies only in project.
set(CMAKE_DEPENDS_IN_PROJECT_ONLY OFF)

# The set of languages for which implicit dependencies are needed:
set(CMAKE_DEPENDS_LANGUAGES
  )

# The set of dependency files which are needed:
set(CMAKE_DEPENDS_DEPENDENCY_FILES
  "/work/main/src/core/basis.c" "CMakeFiles/bsfit_core.dir/src/core/basis.c.o" "gcc" "CMakeFiles/bsfit_core.dir/src/core/basis.c.o.d"
  "/work/main/src/core/curve.c" "CMakeFiles/bsfit_core.dir/src/core/curve.c.o" "gcc" "CMakeFiles/bsfit_core.dir/src/core/curve.c.o.d"
  "/work/main/src/core/knots.c" "CMakeFiles/bsfit_core.dir/src/core/knots.c.o" "gcc" "CMakeFiles/bsfit_core.dir/src/core/knots.c.o.d"
  "/work/main/src/core/memory.c" "CMakeFiles/bsfit_core.dir/src/core/memory.c.o" "gcc" "CMakeFiles/bsfit_core.dir/src/core/memory.c.o.d"
  "/work/main/src/core/status.c" "CMakeFiles/bsfit_core.dir/src/core/status.c.o" "gcc" "CMakeFiles/bsfit_core.dir/src/core/status.c.o.d"
  )

# Targets to which this target links.
set(CMAKE_TARGET_LINKED_INFO_FILES
  )

# Fortran module output directory.
set(CMAKE_Fortran_TARGET_MODULE_DIR "")
