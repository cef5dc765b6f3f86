file(REMOVE_RECURSE
  "libbsfit_core.a"
)
