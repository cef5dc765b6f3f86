CMakeFiles/bsfit_shared.dir/src/core/basis.c.o: \
 /work/main/src/core/basis.c /usr/include/stdc-predef.h \
 /work/main/src/core/internal.h /work/main/src/core/../bsfit.h \
 /usr/lib/gcc/x86_64-linux-gnu/12/include/stddef.h \
 /work/main/src/core/../bsfit_curve_ops.h /work/main/src/core/../bsfit.h \
 /work/main/src/core/../bsfit_surface.h \
 /work/main/src/core/../bsfit_fit.h /work/main/src/core/../bsfit_filter.h \
 /work/main/src/core/../bsfit_io.h
