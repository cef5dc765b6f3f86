/*
** lscan.h
** What the two files of bs.scan share (lscan.c: reading and slicing; lscan_section.c:
** reduction, ordering, IGES of several curves). Private to src/lua.
*/
#ifndef BSFIT_LSCAN_H
#define BSFIT_LSCAN_H

#include "laux.h"

#define BSFIT_SCANTMP_T "bsfit.ScanTemp"

/* Core results held until they are copied into Lua values (a raise in between leaks
** nothing: __gc frees them). */
typedef struct tmp_ud {
  bsfit_sections sec;
  bsfit_order_result ord;
  bsfit_scan scan;
} tmp_ud;

/* Pushes an empty holder (its metatable is made by bsfit__lua_lib_scan). */
tmp_ud *bsfit__lua_scan_tmp(lua_State *L);

/* Sets reduce, order and write_iges in the bs.scan table on the stack top. */
void bsfit__lua_scan_section_funcs(lua_State *L);

#endif
