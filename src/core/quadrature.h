/*
** quadrature.h
** Gauss-Legendre rules, shared by arc length (curve_geom.c) and the L2 projections of the
** filters (filter_reduce.c). Not part of the public API.
*/
#ifndef BSFIT_QUADRATURE_H
#define BSFIT_QUADRATURE_H

/* Nodes x[0..n-1] (increasing) and weights w of the n-point Gauss-Legendre rule on
** [-1, 1], exact for polynomials of degree 2n - 1; n >= 1. Computed per call (Newton's
** method on the Legendre polynomial P_n): no static state. */
void bsfit__gauss_legendre(int n, double *x, double *w);

#endif
