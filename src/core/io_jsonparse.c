/*
** io_jsonparse.c
** A small strict JSON reader (RFC 8259 grammar), pull style: the curve and surface
** readers walk the structure they expect and skip what they do not know. Errors give
** the byte offset. No recursion deeper than BSFIT__JSON_MAXDEPTH, so hostile input
** cannot exhaust the stack.
*/
#include "io_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

bsfit_err bsfit__json_fail(bsfit__json *j, bsfit_err code, const char *what) {
  if (j->pos >= j->len)
    return bsfit__fail(j->st, code, "JSON byte %zu (end of text): %s", j->pos, what);
  return bsfit__fail(j->st, code, "JSON byte %zu: %s", j->pos, what);
}

static void skip_ws(bsfit__json *j) {
  while (j->pos < j->len) {
    char c = j->s[j->pos];
    if (c != ' ' && c != '\t' && c != '\n' && c != '\r') break;
    j->pos++;
  }
}

int bsfit__json_peek(bsfit__json *j) {
  skip_ws(j);
  return j->pos < j->len ? (unsigned char)j->s[j->pos] : -1;
}

bsfit_err bsfit__json_expect(bsfit__json *j, char c) {
  char what[24] = "expected 'x'";
  if (bsfit__json_peek(j) == (unsigned char)c) {
    j->pos++;
    return BSFIT_OK;
  }
  what[10] = c;
  return bsfit__json_fail(j, BSFIT_EFORMAT, what);
}

static int hexval(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

/* One escape after the backslash; returns the byte to store, or -1. */
static int escape(bsfit__json *j) {
  static const char from[] = "\"\\/bfnrt", to[] = "\"\\/\b\f\n\r\t";
  const char *k;
  int i, code = 0;
  if (j->pos >= j->len) return -1;
  k = strchr(from, j->s[j->pos]);
  if (k != NULL && *k != '\0') {
    j->pos++;
    return (unsigned char)to[k - from];
  }
  if (j->s[j->pos] != 'u' || j->len - j->pos < 5) return -1;
  for (i = 1; i <= 4; i++) {
    int h = hexval(j->s[j->pos + (size_t)i]);
    if (h < 0) return -1;
    code = code * 16 + h;
  }
  j->pos += 5;
  return code < 0x80 ? code : '?';
}

bsfit_err bsfit__json_string(bsfit__json *j, char *dst, size_t cap) {
  size_t n = 0;
  bsfit_err e = bsfit__json_expect(j, '"');
  if (e != BSFIT_OK) return e;
  while (j->pos < j->len) {
    unsigned char c = (unsigned char)j->s[j->pos];
    int out;
    if (c == '"') {
      j->pos++;
      dst[n < cap ? n : cap - 1] = '\0';
      return BSFIT_OK;
    }
    if (c < 0x20) return bsfit__json_fail(j, BSFIT_EFORMAT, "control character in a string");
    j->pos++;
    out = c;
    if (c == '\\' && (out = escape(j)) < 0)
      return bsfit__json_fail(j, BSFIT_EFORMAT, "bad escape in a string");
    if (n + 1 < cap) dst[n] = (char)out;
    n++;
  }
  return bsfit__json_fail(j, BSFIT_EFORMAT, "unterminated string");
}

static size_t digits(const bsfit__json *j, size_t i) {
  while (i < j->len && j->s[i] >= '0' && j->s[i] <= '9') i++;
  return i;
}

bsfit_err bsfit__json_number(bsfit__json *j, double *x) {
  char tmp[512], *end;
  size_t i, start;
  skip_ws(j);
  start = i = j->pos;
  /* -?(0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)? checked here; strtod converts */
  if (i < j->len && j->s[i] == '-') i++;
  if (i < j->len && j->s[i] == '0') i++;
  else if (i < j->len && j->s[i] >= '1' && j->s[i] <= '9') i = digits(j, i);
  else return bsfit__json_fail(j, BSFIT_EFORMAT, "expected a number");
  if (i < j->len && j->s[i] == '.') {
    size_t k = digits(j, i + 1);
    if (k == i + 1) return bsfit__json_fail(j, BSFIT_EFORMAT, "digits expected after '.'");
    i = k;
  }
  if (i < j->len && (j->s[i] == 'e' || j->s[i] == 'E')) {
    size_t k = i + 1;
    if (k < j->len && (j->s[k] == '+' || j->s[k] == '-')) k++;
    if (digits(j, k) == k) return bsfit__json_fail(j, BSFIT_EFORMAT, "digits expected in exponent");
    i = digits(j, k);
  }
  if (i - start >= sizeof tmp) return bsfit__json_fail(j, BSFIT_EFORMAT, "number too long");
  memcpy(tmp, j->s + start, i - start);
  tmp[i - start] = '\0';
  *x = strtod(tmp, &end);
  if (!isfinite(*x)) {
    bsfit_err e = bsfit__json_fail(j, BSFIT_ENONFINITE, "number out of double range");
    j->pos = i; /* consumed all the same, so a skipped value can go on */
    return e;
  }
  j->pos = i;
  return BSFIT_OK;
}

static int literal(bsfit__json *j, const char *word) {
  size_t n = strlen(word);
  if (j->len - j->pos < n || memcmp(j->s + j->pos, word, n) != 0) return 0;
  j->pos += n;
  return 1;
}

bsfit_err bsfit__json_bool(bsfit__json *j, int *b) {
  skip_ws(j);
  if (literal(j, "true")) *b = 1;
  else if (literal(j, "false")) *b = 0;
  else return bsfit__json_fail(j, BSFIT_EFORMAT, "expected true or false");
  return BSFIT_OK;
}

static bsfit_err skip_container(bsfit__json *j, char close) {
  bsfit_err e;
  char dummy[1];
  if (++j->depth > BSFIT__JSON_MAXDEPTH)
    return bsfit__json_fail(j, BSFIT_EFORMAT, "nesting too deep");
  j->pos++;
  if (bsfit__json_peek(j) == close) {
    j->pos++;
    j->depth--;
    return BSFIT_OK;
  }
  for (;;) {
    if (close == '}') {
      e = bsfit__json_string(j, dummy, sizeof dummy);
      if (e == BSFIT_OK) e = bsfit__json_expect(j, ':');
      if (e != BSFIT_OK) return e;
    }
    e = bsfit__json_skip(j);
    if (e != BSFIT_OK) return e;
    if (bsfit__json_peek(j) == ',') {
      j->pos++;
      continue;
    }
    e = bsfit__json_expect(j, close);
    if (e == BSFIT_OK) j->depth--;
    return e;
  }
}

bsfit_err bsfit__json_skip(bsfit__json *j) {
  char dummy[1];
  double x;
  switch (bsfit__json_peek(j)) {
    case '{': return skip_container(j, '}');
    case '[': return skip_container(j, ']');
    case '"': return bsfit__json_string(j, dummy, sizeof dummy);
    case 't': case 'f': case 'n':
      if (literal(j, "true") || literal(j, "false") || literal(j, "null")) return BSFIT_OK;
      return bsfit__json_fail(j, BSFIT_EFORMAT, "invalid literal");
    case -1: return bsfit__json_fail(j, BSFIT_EFORMAT, "value expected");
    default: {
      bsfit_err e = bsfit__json_number(j, &x);
      return e == BSFIT_ENONFINITE ? BSFIT_OK : e; /* an unknown key may hold 1e999 */
    }
  }
}

static bsfit_err push(bsfit__json *j, bsfit__numarr *a, double x) {
  if (a->n == a->cap) {
    size_t ncap = a->cap ? 2 * a->cap : 16;
    double *p;
    if (bsfit__mulsize(ncap, sizeof(double)) == 0)
      return bsfit__json_fail(j, BSFIT_ENOMEM, "array too large");
    p = bsfit__realloc(a->a, a->v, a->cap * sizeof(double), ncap * sizeof(double));
    if (p == NULL) return bsfit__json_fail(j, BSFIT_ENOMEM, "out of memory for an array");
    a->v = p;
    a->cap = ncap;
  }
  a->v[a->n++] = x;
  return BSFIT_OK;
}

/* Level `level` of a nested numeric array; the first array seen at a level fixes its
** length, every later one must match (so the result is rectangular). */
static bsfit_err numarray_level(bsfit__json *j, bsfit__numarr *a, int level, int *seen) {
  size_t count = 0;
  bsfit_err e;
  if (level < 0 || level >= 3 || level >= a->depth)
    return bsfit__json_fail(j, BSFIT_EINVAL, "numeric arrays nest at most 3 deep");
  e = bsfit__json_expect(j, '[');
  if (e != BSFIT_OK) return e;
  if (bsfit__json_peek(j) != ']') {
    for (;;) {
      if (level + 1 == a->depth) {
        double x;
        e = bsfit__json_number(j, &x);
        if (e == BSFIT_OK) e = push(j, a, x);
      } else {
        e = numarray_level(j, a, level + 1, seen);
      }
      if (e != BSFIT_OK) return e;
      count++;
      if (bsfit__json_peek(j) != ',') break;
      j->pos++;
    }
  }
  e = bsfit__json_expect(j, ']');
  if (e != BSFIT_OK) return e;
  if (!seen[level]) {
    seen[level] = 1;
    a->shape[level] = count;
  } else if (a->shape[level] != count) {
    return bsfit__json_fail(j, BSFIT_EFORMAT, "arrays of different lengths (ragged)");
  }
  return BSFIT_OK;
}

bsfit_err bsfit__json_numarray(bsfit__json *j, bsfit__numarr *a) {
  int seen[3] = {0, 0, 0};
  return numarray_level(j, a, 0, seen);
}

void bsfit__numarr_free(bsfit__numarr *a) {
  bsfit__free(a->a, a->v, a->cap * sizeof(double));
  a->v = NULL;
  a->n = a->cap = 0;
}

bsfit_err bsfit__json_end(bsfit__json *j) {
  if (bsfit__json_peek(j) != -1)
    return bsfit__json_fail(j, BSFIT_EFORMAT, "trailing characters after the document");
  return BSFIT_OK;
}
