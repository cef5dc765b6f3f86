# Empty dependencies file for bsfit_core.
# This may be replaced when dependencies are built.
