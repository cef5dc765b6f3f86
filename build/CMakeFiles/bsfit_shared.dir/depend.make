# Empty dependencies file for bsfit_shared.
# This may be replaced when dependencies are built.
