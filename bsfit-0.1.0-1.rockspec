-- bsfit-0.1.0-1.rockspec: `luarocks --lua-version 5.4 make` from a checkout builds the bsfit
-- C module (the binding and libbsfit's core, statically) with CMake and installs it with
-- the Lua modules (strategies, weighting rules, the commands) into the rocks tree.
-- Needs the Debian packages cmake, pkg-config, liblua5.4-dev, liblapacke-dev, libopenblas-dev.
rockspec_format = "3.0"
package = "bsfit"
version = "0.1.0-1"
-- `luarocks make` builds the checkout it runs in and never fetches `source`; the URL is where
-- a published rock would be fetched from (set it when the repository is published).
source = {
  url = "git+https://example.invalid/bsfit.git",
  tag = "v0.1.0",
}
description = {
  summary = "B-spline curve fitting and smoothing for scanned sections (C engine, Lua 5.4)",
  detailed = [[
Fits smooth closed B-splines to the ordered points of scanned cross-sections by weighted
least squares (the Pereira & Carvalho method, a true periodic fit and an automatic
strategy that reads the noise level), and smooths splines by box filtering their control
points. Curves, surfaces, knots, fitters and point sets are userdata backed by a C library
(banded solves through LAPACKE).
]],
  license = "MIT",
  labels = { "b-spline", "nurbs", "curve-fitting", "cad" },
}
dependencies = {
  "lua >= 5.4, < 5.5",
}
build = {
  type = "cmake",
  variables = {
    CMAKE_BUILD_TYPE = "Release",
    CMAKE_INSTALL_PREFIX = "$(PREFIX)",
    BSFIT_TESTS = "OFF",
    BSFIT_BENCH = "OFF",
    BSFIT_INSTALL_LUA_ONLY = "ON",
    BSFIT_INSTALL_LUADIR = "$(LUADIR)",
    BSFIT_INSTALL_LUACDIR = "$(LIBDIR)",
  },
}
