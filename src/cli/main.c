/*
** main.c
** The bsfit program: lua.c's structure (main -> lua_pcall(pmain), collectargs,
** the `arg` table, -e/-l/-i/-v/-E/-W, l_message to stderr) over a bsfit engine,
** which preloads the bsfit module and puts the shipped lua/ directory on the
** module path. A first argument that is a plain word names a subcommand, the
** Lua module bsfit.cli.<word> of that directory, whose main(args) is run.
*/
#define _POSIX_C_SOURCE 200809L

#include "bsfit.h"
#include "bsfit_engine.h"
#include "bsfit_lua.h"

#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define PROGNAME "bsfit"

/* What collectargs found, as bit flags (lua.c's has_*). */
enum { HAS_ERROR = 1, HAS_I = 2, HAS_V = 4, HAS_E = 8, HAS_UPPER_E = 16, HAS_HELP = 32,
       HAS_VERSION = 64 };

/* Everything main hands to pmain: no static mutable state. */
typedef struct cli {
  int argc;
  char **argv;
  int script;         /* index of the script or subcommand in argv, or 0 */
  int flags;
  int debug;          /* --debug: messages keep their Lua traceback */
  int status;         /* the process exit status pmain decides */
  bsfit_engine *e;
  bsfit_engine_opts opts;
} cli;

/* The program's only static: a signal handler receives no context (lua.c's
** globalL). Set once the engine exists, read only by on_sigint. */
static bsfit_engine *volatile sigint_engine = NULL;

/* Ctrl-C stops the running script with a traceback (lua.c's laction); a second
** Ctrl-C, with the default action back, ends the process at once. */
static void on_sigint(int sig) {
  signal(sig, SIG_DFL);
  bsfit_engine_interrupt(sigint_engine);
}

/* {====================================================================
** Messages
** ===================================================================== */

static void print_usage(FILE *f) {
  fprintf(f,
          "usage: " PROGNAME " [options] [script [args]]\n"
          "       " PROGNAME " COMMAND [args]      run lua/bsfit/cli/COMMAND.lua (e.g. reconstruct, filter)\n"
          "Available options are:\n"
          "  -e stat          execute string 'stat'\n"
          "  -i               enter interactive mode after executing 'script'\n"
          "  -l mod           require library 'mod' into global 'mod'\n"
          "  -v               show version information\n"
          "  -E               ignore environment variables (BSFIT_PATH, LUA_PATH)\n"
          "  -W               turn warnings on\n"
          "  --sandbox        run without io, os, debug, C modules and bytecode\n"
          "  --mem-limit N    cap the Lua heap at N bytes (suffixes k, m, g)\n"
          "  --instr-limit N  stop any call after N Lua instructions (e.g. 1e8)\n"
          "  --debug          print the Lua traceback with an error message\n"
          "  --version        print the version and exit\n"
          "  -h, --help       print this help and exit (COMMAND --help: the command's)\n"
          "  --               stop handling options\n"
          "  -                stop handling options and execute stdin\n"
          "The bsfit module is preloaded: local bs = require \"bsfit\".\n"
          "Lua modules are searched first in $BSFIT_PATH, else in the shipped lua/ directory.\n");
}

static void l_message(const char *msg) {
  fprintf(stderr, "%s: %s\n", PROGNAME, msg);
  fflush(stderr);
}

static void print_version(void) {
  printf(PROGNAME " %s (%s)\n", bsfit_version(), LUA_RELEASE);
  fflush(stdout);
}

/* Reports a failed engine call; returns 0 so callers can `return report(...)`. The
** traceback the engine appends is for developers: printed with --debug only. */
static int report(cli *c, bsfit_err code) {
  if (code != BSFIT_OK) {
    const char *msg = bsfit_engine_errmsg(c->e), *tb = strstr(msg, "\nstack traceback:");
    if (tb != NULL && !c->debug) fprintf(stderr, "%s: %.*s\n", PROGNAME, (int)(tb - msg), msg);
    else l_message(msg);
    c->status = EXIT_FAILURE;
    return 0;
  }
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** Arguments (lua.c's collectargs, plus our long options)
** ===================================================================== */

/* Parses a count with an optional k/m/g suffix (powers of 1024), written as an
** integer or in exponent notation (1e8, 2.5e6: a whole number); 0 on error. */
static size_t parse_size(const char *s) {
  char *end;
  unsigned long long v;
  double d;
  errno = 0;
  v = strtoull(s, &end, 10);
  if (errno != 0 || end == s || s[0] == '-') return 0;
  if (*end == '.' || *end == 'e' || *end == 'E') {
    d = strtod(s, &end);
    if (errno != 0 || !(d >= 1 && d < 1.8e19) || d != floor(d)) return 0;
    v = (unsigned long long)d;
  }
  switch (*end) {
    case 'k': case 'K': v <<= 10; end++; break;
    case 'm': case 'M': v <<= 20; end++; break;
    case 'g': case 'G': v <<= 30; end++; break;
    default: break;
  }
  return *end == '\0' ? (size_t)v : 0;
}

/* Long options; returns 0 on an error (with the bad argument at *i). */
static int long_option(cli *c, int *i) {
  char **argv = c->argv;
  const char *o = argv[*i];
  if (strcmp(o, "--help") == 0) c->flags |= HAS_HELP;
  else if (strcmp(o, "--version") == 0) c->flags |= HAS_VERSION;
  else if (strcmp(o, "--sandbox") == 0) c->opts.sandbox = 1;
  else if (strcmp(o, "--debug") == 0) c->debug = 1;
  else if (strcmp(o, "--mem-limit") == 0 || strcmp(o, "--instr-limit") == 0) {
    size_t v;
    if (argv[*i + 1] == NULL || (v = parse_size(argv[*i + 1])) == 0) return 0;
    if (o[2] == 'm') c->opts.mem_limit = v;
    else c->opts.instr_budget = v;
    (*i)++;
  } else {
    return 0;
  }
  return 1;
}

/* Sets c->script to the first non-option (0 if none) and c->flags; on a bad
** option HAS_ERROR with c->script at the offending argument (lua.c's contract). */
static void collectargs(cli *c) {
  char **argv = c->argv;
  int i;
  for (i = 1; argv[i] != NULL; i++) {
    c->script = i;
    if (argv[i][0] != '-') return;       /* not an option: the script */
    switch (argv[i][1]) {
      case '-':
        if (argv[i][2] == '\0') {        /* "--": the next argument is the script */
          c->script = argv[i + 1] != NULL ? i + 1 : 0;
          return;
        }
        if (!long_option(c, &i)) goto bad;
        break;
      case '\0': return;                 /* "-": stdin is the script */
      case 'E': if (argv[i][2] != '\0') goto bad; c->flags |= HAS_UPPER_E; break;
      case 'h': if (argv[i][2] != '\0') goto bad; c->flags |= HAS_HELP; break;
      case 'W': if (argv[i][2] != '\0') goto bad; break;
      case 'i': if (argv[i][2] != '\0') goto bad; c->flags |= HAS_I | HAS_V; break;
      case 'v': if (argv[i][2] != '\0') goto bad; c->flags |= HAS_V; break;
      case 'e':
      case 'l':
        if (argv[i][1] == 'e') c->flags |= HAS_E;
        if (argv[i][2] == '\0') {        /* no concatenated argument: take the next */
          i++;
          if (argv[i] == NULL || argv[i][0] == '-') goto bad;
        }
        break;
      default: goto bad;
    }
  }
  c->script = 0;
  return;
bad:
  c->flags = HAS_ERROR;
  c->script = argv[i] != NULL ? i : i - 1;
}

/* lua.c's createargtable: script at 0, its arguments at 1.., options below 0;
** without a script the program name is at 0 and the options follow. */
static void createargtable(lua_State *L, cli *c) {
  int i, first = c->script;
  lua_createtable(L, c->argc - first, first + 1);
  for (i = 0; i < c->argc; i++) {
    lua_pushstring(L, c->argv[i]);
    lua_rawseti(L, -2, i - first);
  }
  lua_setglobal(L, "arg");
}

/* }==================================================================== */

/* {====================================================================
** Running things
** ===================================================================== */

static int dostring(cli *c, const char *s) {
  return report(c, bsfit_engine_run_string(c->e, s, "=(command line)"));
}

/* -l mod: require it into global mod (lua.c's dolibrary). */
static int dolibrary(cli *c, const char *name) {
  lua_State *L = bsfit_engine_lua(c->e);
  lua_getglobal(L, "require");
  lua_pushstring(L, name);
  if (!report(c, bsfit_engine_pcall(c->e, 1, 1))) return 0;
  lua_setglobal(L, name);
  return 1;
}

/* -e and -l in their order on the command line. */
static int runargs(cli *c) {
  int i, n = c->script != 0 ? c->script : c->argc;
  for (i = 1; i < n; i++) {
    const char *a = c->argv[i];
    int opt = a[0] == '-' ? a[1] : 0;
    if (opt == 'W') lua_warning(bsfit_engine_lua(c->e), "@on", 0);
    if (opt == 'e' || opt == 'l') {
      const char *extra = a[2] != '\0' ? a + 2 : c->argv[++i];
      if (!(opt == 'e' ? dostring(c, extra) : dolibrary(c, extra))) return 0;
    }
    if (strcmp(a, "--mem-limit") == 0 || strcmp(a, "--instr-limit") == 0) i++;
  }
  return 1;
}

/* Pushes the script's arguments (lua.c's pushargs); returns how many. */
static int pushargs(lua_State *L, cli *c) {
  int i, n = c->argc - c->script - 1;
  luaL_checkstack(L, n + 3, "too many arguments to script");
  for (i = 1; i <= n; i++) lua_pushstring(L, c->argv[c->script + i]);
  return n;
}

static int handle_script(cli *c) {
  lua_State *L = bsfit_engine_lua(c->e);
  const char *fname = c->argv[c->script];
  int n;
  if (strcmp(fname, "-") == 0 && strcmp(c->argv[c->script - 1], "--") != 0) fname = NULL;
  if (!report(c, bsfit_engine_load(c->e, fname))) return 0;
  n = pushargs(L, c);
  return report(c, bsfit_engine_pcall(c->e, n, 0));
}

/* A plain word: letters, digits, '_' and '-', not starting with '-'. */
static int is_word(const char *s) {
  if (s[0] == '\0' || s[0] == '-') return 0;
  for (; *s != '\0'; s++)
    if (!(('a' <= *s && *s <= 'z') || ('A' <= *s && *s <= 'Z') || ('0' <= *s && *s <= '9') ||
          *s == '_' || *s == '-'))
      return 0;
  return 1;
}

/* Whether lua/bsfit/cli/<word>.lua (or <word>/init.lua) exists. */
static int has_command(cli *c, const char *word) {
  static const char *const pats[] = {"%s/bsfit/cli/%s.lua", "%s/bsfit/cli/%s/init.lua"};
  const char *dir = bsfit_engine_luadir(c->e);
  char path[4096];
  size_t i;
  if (dir[0] == '\0') return 0;
  for (i = 0; i < sizeof pats / sizeof pats[0]; i++) {
    int n = snprintf(path, sizeof path, pats[i], dir, word);
    if (n > 0 && (size_t)n < sizeof path && access(path, R_OK) == 0) return 1;
  }
  return 0;
}

/* Runs require("bsfit.cli.<word>").main(args); its integer result is the exit status. */
static int handle_command(cli *c, const char *word) {
  lua_State *L = bsfit_engine_lua(c->e);
  int i, n = c->argc - c->script - 1;
  lua_getglobal(L, "require");
  lua_pushfstring(L, "bsfit.cli.%s", word);
  if (!report(c, bsfit_engine_pcall(c->e, 1, 1))) return 0;
  if (lua_type(L, -1) != LUA_TTABLE || lua_getfield(L, -1, "main") != LUA_TFUNCTION) {
    fprintf(stderr, PROGNAME ": module bsfit.cli.%s has no main function\n", word);
    c->status = EXIT_FAILURE;
    return 0;
  }
  lua_remove(L, -2);
  lua_createtable(L, n, 0);
  for (i = 1; i <= n; i++) {
    lua_pushstring(L, c->argv[c->script + i]);
    lua_rawseti(L, -2, i);
  }
  if (!report(c, bsfit_engine_pcall(c->e, 1, 1))) return 0;
  if (lua_isinteger(L, -1))
    c->status = (int)lua_tointeger(L, -1);
  else if (lua_isboolean(L, -1) && !lua_toboolean(L, -1))
    c->status = EXIT_FAILURE;
  lua_pop(L, 1);
  return 1;
}

/* }==================================================================== */

/* {====================================================================
** Interactive mode (a plain line reader: lua.c's REPL without readline)
** ===================================================================== */

/* Whether the load error on the stack means "the statement is not finished". */
static int incomplete(lua_State *L, int status) {
  size_t lmsg;
  const char *msg;
  if (status != LUA_ERRSYNTAX) return 0;
  msg = lua_tolstring(L, -1, &lmsg);
  return lmsg >= 5 && strcmp(msg + lmsg - 5, "<eof>") == 0;
}

/* Reads one statement (lines until it parses) and leaves it compiled on the stack;
** returns -1 at end of input, else the load status (message on the stack). */
static int loadline(lua_State *L) {
  char line[1024];
  int status;
  fputs("> ", stdout);
  fflush(stdout);
  if (fgets(line, sizeof line, stdin) == NULL) return -1;
  line[strcspn(line, "\n")] = '\0';
  lua_pushfstring(L, "return %s", line); /* first try it as an expression */
  status = luaL_loadbufferx(L, lua_tostring(L, -1), lua_rawlen(L, -1), "=stdin", "t");
  lua_remove(L, -2);
  if (status == LUA_OK) return status;
  lua_pop(L, 1);
  lua_pushstring(L, line);
  for (;;) {
    status = luaL_loadbufferx(L, lua_tostring(L, -1), lua_rawlen(L, -1), "=stdin", "t");
    if (!incomplete(L, status)) break;
    lua_pop(L, 1);
    fputs(">> ", stdout);
    fflush(stdout);
    if (fgets(line, sizeof line, stdin) == NULL) break;
    line[strcspn(line, "\n")] = '\0';
    lua_pushfstring(L, "\n%s", line);
    lua_concat(L, 2);
  }
  lua_remove(L, -2);
  return status;
}

static void doREPL(cli *c) {
  lua_State *L = bsfit_engine_lua(c->e);
  int status;
  while ((status = loadline(L)) != -1) {
    int base = lua_gettop(L) - 1, n;
    if (status != LUA_OK) {
      l_message(lua_tostring(L, -1));
      lua_pop(L, 1);
      continue;
    }
    if (bsfit_engine_pcall(c->e, 0, LUA_MULTRET) != BSFIT_OK) {
      l_message(bsfit_engine_errmsg(c->e));
      continue;
    }
    n = lua_gettop(L) - base;
    if (n > 0) { /* print the results with the global print */
      lua_getglobal(L, "print");
      lua_insert(L, base + 1);
      if (bsfit_engine_pcall(c->e, n, 0) != BSFIT_OK) l_message(bsfit_engine_errmsg(c->e));
    }
  }
  lua_settop(L, 0);
  fputs("\n", stdout);
  fflush(stdout);
}

/* }==================================================================== */

/* Runs in protected mode (lua.c's pmain): what raises here is a bug or lack of memory. */
static int pmain(lua_State *L) {
  cli *c = (cli *)lua_touserdata(L, 1);
  lua_settop(L, 0);
  createargtable(L, c);
  if (!runargs(c)) return 0;
  if (c->script != 0) {
    const char *word = c->argv[c->script];
    int after_dashes = strcmp(c->argv[c->script - 1], "--") == 0;
    if (!after_dashes && is_word(word) && has_command(c, word)) {
      if (bsfit_lua_sandboxed(L)) { /* the engine's flag: commands read and write files */
        fprintf(stderr, PROGNAME ": '%s' reads and writes files: not available with --sandbox\n",
                word);
        c->status = EXIT_FAILURE;
        return 0;
      }
      handle_command(c, word);
      return 0;
    }
    if (!after_dashes && is_word(word) && access(word, R_OK) != 0) {
      fprintf(stderr, PROGNAME ": unknown command '%s' (see '" PROGNAME " --help')\n", word);
      c->status = EXIT_FAILURE;
      return 0;
    }
    if (!handle_script(c)) return 0;
  }
  if (c->flags & HAS_I) doREPL(c);
  return 0;
}

int main(int argc, char **argv) {
  static const bsfit_engine_opts defaults = {0, 0, 0, NULL, NULL};
  cli c;
  lua_State *L;
  memset(&c, 0, sizeof c);
  c.argc = argc;
  c.argv = argv;
  c.opts = defaults;
  c.opts.argv0 = argv[0];
  c.status = EXIT_SUCCESS;
  (void)bsfit_blas_single_thread(); /* idle OpenBLAS workers would spin next to -j N */
  /* Options are read before the engine exists: they choose how it is built. */
  collectargs(&c);
  if (c.flags & HAS_ERROR) {
    const char *bad = argv[c.script];
    if (strcmp(bad, "--mem-limit") == 0 || strcmp(bad, "--instr-limit") == 0)
      fprintf(stderr, PROGNAME ": '%s' needs a positive number\n", bad);
    else
      fprintf(stderr, PROGNAME ": unrecognized option '%s'\n", bad);
    print_usage(stderr);
    return EXIT_FAILURE;
  }
  if (c.flags & HAS_HELP) {
    print_usage(stdout);
    return EXIT_SUCCESS;
  }
  if (c.flags & (HAS_VERSION | HAS_V)) print_version();
  if (c.flags & HAS_VERSION) return EXIT_SUCCESS;
  if (argc <= 1) { /* no arguments: help, as `git` does, rather than a REPL */
    print_usage(stdout);
    return EXIT_SUCCESS;
  }
  if (c.flags & HAS_UPPER_E) { /* -E: the engine must not see BSFIT_PATH, Lua's LUA_PATH* */
    unsetenv("BSFIT_PATH");
    unsetenv("LUA_PATH");
    unsetenv("LUA_PATH_5_4");
    unsetenv("LUA_CPATH");
    unsetenv("LUA_CPATH_5_4");
  }
  c.e = bsfit_engine_new(&c.opts);
  if (c.e == NULL) {
    l_message("cannot create the Lua state: not enough memory");
    return EXIT_FAILURE;
  }
  L = bsfit_engine_lua(c.e);
  sigint_engine = c.e;
  signal(SIGINT, on_sigint);
  lua_pushcfunction(L, pmain);
  lua_pushlightuserdata(L, &c);
  if (lua_pcall(L, 1, 0, 0) != LUA_OK) {
    l_message(lua_tostring(L, -1));
    c.status = EXIT_FAILURE;
  }
  signal(SIGINT, SIG_DFL);
  sigint_engine = NULL;
  bsfit_engine_free(c.e);
  return c.status;
}
