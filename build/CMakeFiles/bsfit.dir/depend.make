# Empty dependencies file for bsfit.
# This may be replaced when dependencies are built.
