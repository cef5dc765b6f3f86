/*
** fuzz_engine.c
** The sandboxed engine driven by fuzzed Lua source: a fresh engine per input with the
** sandbox on, a 16 MB memory cap and a budget of 10^6 instructions; the bytes run as a
** chunk (prefixed, half the time, with `local bs = require "bsfit"` so the binding is
** reached), then a second small chunk checks that the engine still answers. Contract:
** every call returns (no crash, no hang: libFuzzer's -timeout catches a hang), and the
** engine works after whatever the script did.
*/
#include "fuzz_util.h"

#include "bsfit_engine.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  static const char prefix[] = "local bs = require 'bsfit'\n";
  bsfit_engine_opts o;
  bsfit_engine *e;
  char *src;
  size_t off = 0;
  if (size > 1 << 16) return 0;
  memset(&o, 0, sizeof o);
  o.sandbox = 1;
  o.mem_limit = 16u << 20;
  o.instr_budget = 1000000;
  o.lua_path = BSFIT_LUA_DIR;
  e = bsfit_engine_new(&o);
  if (e == NULL) return 0;
  src = malloc(sizeof prefix + size);
  if (src == NULL) abort();
  if (size > 0 && data[0] % 2 == 0) {
    memcpy(src, prefix, sizeof prefix - 1);
    off = sizeof prefix - 1;
  }
  memcpy(src + off, data, size);
  src[off + size] = '\0';
  (void)bsfit_engine_run_string(e, src, "=fuzz");
  if (bsfit_engine_run_string(e, "return 1 + 1", "=after") != BSFIT_OK)
    fz_fail("engine: no longer answers after a script", bsfit_engine_errmsg(e));
  bsfit_engine_free(e);
  free(src);
  return 0;
}
