# cmake/install.cmake: the installed engine library, the install rules, and the
# pkg-config and CMake packages. Included by CMakeLists.txt after the targets.
#
#   cmake --install build --prefix P   installs
#     P/lib/libbsfit.{so,a}             the core (bsfit::bsfit, bsfit::bsfit_static; bsfit.pc)
#     P/lib/libbsfit_engine.{so,a}      the binding + the embedding engine, on libbsfit and
#                                       liblua5.4 (bsfit::engine, bsfit::engine_static;
#                                       bsfit-engine.pc)
#     P/include/bsfit*.h, P/bin/bsfit, P/share/man/man1/bsfit.1, P/share/bsfit/demo/
#     P/lib/lua/5.4/bsfit.so, P/share/lua/5.4/bsfit/...   where stock lua5.4 looks
#     P/lib/cmake/bsfit/                find_package(bsfit)
# With BSFIT_INSTALL_LUA_ONLY (the rockspec) only the Lua module and the Lua files.

# Path from directory `from` to directory `to`, both relative to the prefix (or absolute).
function(bsfit_relpath out from to)
  foreach(v from to)
    if(NOT IS_ABSOLUTE "${${v}}")
      set(${v} "/prefix/${${v}}")
    endif()
  endforeach()
  file(RELATIVE_PATH rel "${from}" "${to}")
  set(${out} "${rel}" PARENT_SCOPE)
endfunction()

bsfit_relpath(BSFIT_LUA_FROM_BIN "${CMAKE_INSTALL_BINDIR}" "${BSFIT_INSTALL_LUADIR}")
bsfit_relpath(BSFIT_LUA_FROM_LIB "${CMAKE_INSTALL_LIBDIR}" "${BSFIT_INSTALL_LUADIR}")
if(TARGET bsfit_lua AND BSFIT_HOST_SOURCES)
  target_compile_definitions(bsfit_lua PRIVATE BSFIT_LUA_DIR_FROM_BIN="${BSFIT_LUA_FROM_BIN}")
endif()

# ---------------------------------------------------------------------------
# libbsfit_engine: the same binding and engine sources as bsfit_lua, built for
# installation: no build-tree fallback for the Lua modules, which it finds next to
# itself (P/lib/../share/lua/5.4) or in the configured prefix.
if(BSFIT_LUA_SOURCES AND BSFIT_HOST_SOURCES AND NOT BSFIT_INSTALL_LUA_ONLY)
  add_library(bsfit_engine_obj OBJECT ${BSFIT_LUA_SOURCES} ${BSFIT_HOST_SOURCES})
  target_include_directories(bsfit_engine_obj PRIVATE ${CMAKE_SOURCE_DIR}/src ${LUA_INCLUDE_DIRS})
  target_compile_definitions(bsfit_engine_obj PRIVATE BSFIT_BUILDING
    BSFIT_LUA_DIR_INSTALL="${BSFIT_LUA_DIR_INSTALL}"
    BSFIT_LUA_DIR_FROM_BIN="${BSFIT_LUA_FROM_BIN}"
    BSFIT_LUA_DIR_FROM_LIB="${BSFIT_LUA_FROM_LIB}")
  target_compile_options(bsfit_engine_obj PRIVATE ${BSFIT_WARNINGS})

  add_library(bsfit_engine SHARED $<TARGET_OBJECTS:bsfit_engine_obj>)
  set_target_properties(bsfit_engine PROPERTIES VERSION ${PROJECT_VERSION}
                        SOVERSION ${PROJECT_VERSION_MAJOR} EXPORT_NAME engine)
  target_link_libraries(bsfit_engine PUBLIC bsfit_shared PkgConfig::LUA
                        PRIVATE Threads::Threads ${CMAKE_DL_LIBS})

  add_library(bsfit_engine_static STATIC $<TARGET_OBJECTS:bsfit_engine_obj>)
  set_target_properties(bsfit_engine_static PROPERTIES OUTPUT_NAME bsfit_engine
                        EXPORT_NAME engine_static)
  target_link_libraries(bsfit_engine_static PUBLIC bsfit_core PkgConfig::LUA Threads::Threads
                        ${CMAKE_DL_LIBS})
  foreach(t bsfit_engine bsfit_engine_static)
    target_include_directories(${t} PUBLIC $<BUILD_INTERFACE:${CMAKE_SOURCE_DIR}/src>
                               $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  endforeach()
  set(BSFIT_ENGINE_TARGETS bsfit_engine bsfit_engine_static)
endif()

# ---------------------------------------------------------------------------
# The Lua module and its Lua files: always
if(BSFIT_LUA_SOURCES)
  install(TARGETS bsfit_module LIBRARY DESTINATION ${BSFIT_INSTALL_LUACDIR})
endif()
install(DIRECTORY ${CMAKE_SOURCE_DIR}/lua/bsfit DESTINATION ${BSFIT_INSTALL_LUADIR})
if(BSFIT_INSTALL_LUA_ONLY)
  # LuaRocks builds `all`: only the module (and the static core it links) is needed
  foreach(t bsfit bsfit_shared bsfit_lua)
    if(TARGET ${t})
      set_target_properties(${t} PROPERTIES EXCLUDE_FROM_ALL ON)
    endif()
  endforeach()
  return()
endif()

# ---------------------------------------------------------------------------
# Libraries, headers, program, man page, demo set
set(BSFIT_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/bsfit)
install(TARGETS bsfit RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS bsfit_shared bsfit_core ${BSFIT_ENGINE_TARGETS} EXPORT bsfitTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
file(GLOB BSFIT_PUBLIC_HEADERS ${CMAKE_SOURCE_DIR}/src/bsfit.h ${CMAKE_SOURCE_DIR}/src/bsfit_*.h)
install(FILES ${BSFIT_PUBLIC_HEADERS} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES ${CMAKE_SOURCE_DIR}/docs/bsfit.1 DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
install(DIRECTORY ${CMAKE_SOURCE_DIR}/tests/data/demo/ DESTINATION ${CMAKE_INSTALL_DATADIR}/bsfit/demo)
install(FILES ${CMAKE_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/bsfit)

# ---------------------------------------------------------------------------
# pkg-config: relocatable (prefix from the .pc file's own place), so an install
# with `--prefix P` other than the configured one still works.
bsfit_relpath(BSFIT_PC_PREFIX "${CMAKE_INSTALL_LIBDIR}/pkgconfig" "")
string(REGEX REPLACE "/$" "" BSFIT_PC_PREFIX "${BSFIT_PC_PREFIX}")
foreach(pc bsfit bsfit-engine)
  configure_file(${CMAKE_SOURCE_DIR}/cmake/${pc}.pc.in ${CMAKE_BINARY_DIR}/${pc}.pc @ONLY)
  install(FILES ${CMAKE_BINARY_DIR}/${pc}.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endforeach()

# ---------------------------------------------------------------------------
# CMake package: find_package(bsfit) -> bsfit::bsfit (core), bsfit::engine
include(CMakePackageConfigHelpers)
install(EXPORT bsfitTargets NAMESPACE bsfit:: DESTINATION ${BSFIT_CMAKE_DIR})
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/bsfitConfig.cmake.in
  ${CMAKE_BINARY_DIR}/bsfitConfig.cmake INSTALL_DESTINATION ${BSFIT_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/bsfitConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES ${CMAKE_BINARY_DIR}/bsfitConfig.cmake ${CMAKE_BINARY_DIR}/bsfitConfigVersion.cmake
        DESTINATION ${BSFIT_CMAKE_DIR})
