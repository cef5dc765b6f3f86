/*
** fuzz_json.c
** The JSON readers, curve and surface, on the same bytes. Contract: OK => the object
** is valid with every number finite, and writing it and reading it back gives the
** same numbers bit for bit; on error the output is left empty.
*/
#include "fuzz_util.h"

static void roundtrip_curve(const bsfit_curve *c) {
  char *s = NULL;
  size_t len = 0;
  bsfit_curve d;
  bsfit_status st;
  size_t nk = c->n + (size_t)c->degree + 1;
  if (bsfit_curve_to_json(c, &s, &len, NULL, &st) != BSFIT_OK) fz_fail("json: to_json", st.msg);
  bsfit_curve_init(&d);
  if (bsfit_curve_from_json(s, len, &d, NULL, &st) != BSFIT_OK) fz_fail("json: reread", st.msg);
  if (d.n != c->n || d.degree != c->degree || d.dim != c->dim || d.periodic != c->periodic ||
      memcmp(d.knots, c->knots, nk * sizeof(double)) != 0 ||
      memcmp(d.ctrl, c->ctrl, c->n * (size_t)c->dim * sizeof(double)) != 0 ||
      (d.weights == NULL) != (c->weights == NULL) ||
      (c->weights && memcmp(d.weights, c->weights, c->n * sizeof(double)) != 0))
    fz_fail("json: curve round trip", NULL);
  bsfit_curve_free(&d);
  free(s);
}

static void check_surface(const bsfit_surface *s) {
  bsfit_status st;
  char *t = NULL;
  size_t len = 0;
  bsfit_surface d;
  if (bsfit_surface_validate(s, &st) != BSFIT_OK) fz_fail("json: surface valid", st.msg);
  fz_check_finite(s->ctrl, s->nu * s->nv * (size_t)s->dim, "json: surface points");
  if (bsfit_surface_to_json(s, &t, &len, NULL, &st) != BSFIT_OK)
    fz_fail("json: surface out", st.msg);
  bsfit_surface_init(&d);
  if (bsfit_surface_from_json(t, len, &d, NULL, &st) != BSFIT_OK)
    fz_fail("json: surface reread", st.msg);
  if (d.nu != s->nu || d.nv != s->nv ||
      memcmp(d.ctrl, s->ctrl, s->nu * s->nv * (size_t)s->dim * sizeof(double)) != 0)
    fz_fail("json: surface round trip", NULL);
  bsfit_surface_free(&d);
  free(t);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  bsfit_curve c;
  bsfit_surface s;
  bsfit_status st;
  bsfit_curve_init(&c);
  if (bsfit_curve_from_json((const char *)data, size, &c, NULL, &st) == BSFIT_OK) {
    fz_check_curve(&c, "json: curve");
    roundtrip_curve(&c);
  } else if (c.n != 0 || c.knots != NULL) {
    fz_fail("json: curve not empty after an error", st.msg);
  }
  bsfit_curve_free(&c);
  bsfit_surface_init(&s);
  if (bsfit_surface_from_json((const char *)data, size, &s, NULL, &st) == BSFIT_OK)
    check_surface(&s);
  bsfit_surface_free(&s);
  return 0;
}
