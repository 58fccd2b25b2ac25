/* bspline.c - clamped uniform B-spline evaluation with derivatives. */
#include "satf/geometry.h"

#include <math.h>
#include <string.h>

#define BSPLINE_MAX_DEGREE 3
#define BSPLINE_MAX_DERIV 2

int satf_bspline_degree(int n) {
  if (n < 1)
    return 0;
  return n - 1 < BSPLINE_MAX_DEGREE ? n - 1 : BSPLINE_MAX_DEGREE;
}

/* Knot j of the open-uniform vector for n control points and degree p:
 * p + 1 zeros, evenly spaced interior knots, p + 1 ones. */
static double clamped_knot(int j, int n, int p) {
  if (j <= p)
    return 0.0;
  if (j >= n)
    return 1.0;
  return (double)(j - p) / (double)(n - p);
}

/* Index of the knot span [U[s], U[s+1]) holding t, with t = 1 put in the
 * last non-empty span so the end point is reached. */
static int knot_span(double t, int n, int p) {
  if (t >= 1.0)
    return n - 1;
  int s = p + (int)floor(t * (double)(n - p));
  if (s < p)
    s = p;
  if (s > n - 1)
    s = n - 1;
  return s;
}

/* Non-zero basis functions N_{span-p+j,p}(t) and their first nd derivatives
 * (Piegl & Tiller, The NURBS Book, algorithm A2.3); ders[k][j] is the k-th
 * derivative of the j-th basis function. */
static void
basis_derivatives(double t, int span, int n, int p, int nd,
                  double ders[BSPLINE_MAX_DERIV + 1][BSPLINE_MAX_DEGREE + 1]) {
  double ndu[BSPLINE_MAX_DEGREE + 1][BSPLINE_MAX_DEGREE + 1];
  double left[BSPLINE_MAX_DEGREE + 1], right[BSPLINE_MAX_DEGREE + 1];
  double a[2][BSPLINE_MAX_DEGREE + 1];

  ndu[0][0] = 1.0;
  for (int j = 1; j <= p; j++) {
    left[j] = t - clamped_knot(span + 1 - j, n, p);
    right[j] = clamped_knot(span + j, n, p) - t;
    double saved = 0.0;
    for (int r = 0; r < j; r++) {
      ndu[j][r] = right[r + 1] + left[j - r];
      double temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  memset(ders, 0,
         sizeof(double) * (BSPLINE_MAX_DERIV + 1) * (BSPLINE_MAX_DEGREE + 1));
  for (int j = 0; j <= p; j++)
    ders[0][j] = ndu[j][p];

  for (int r = 0; r <= p; r++) {
    int s1 = 0, s2 = 1;
    a[0][0] = 1.0;
    for (int k = 1; k <= nd; k++) {
      double d = 0.0;
      int rk = r - k, pk = p - k;
      if (r >= k) {
        a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
        d = a[s2][0] * ndu[rk][pk];
      }
      int j1 = rk >= -1 ? 1 : -rk;
      int j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (int j = j1; j <= j2; j++) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
        d += a[s2][k] * ndu[r][pk];
      }
      ders[k][r] = d;
      int tmp = s1;
      s1 = s2;
      s2 = tmp;
    }
  }
  double scale = (double)p;
  for (int k = 1; k <= nd; k++) {
    for (int j = 0; j <= p; j++)
      ders[k][j] *= scale;
    scale *= (double)(p - k);
  }
}

void satf_bspline_eval(const float *ctrl, int n, int dim, double t,
                       double *value, double *d1, double *d2) {
  double *out[BSPLINE_MAX_DERIV + 1] = {value, d1, d2};
  if (!(t > 0.0))
    t = 0.0; /* also maps NaN to the start rather than reading out of range */
  if (t > 1.0)
    t = 1.0;
  int p = satf_bspline_degree(n);
  int span = knot_span(t, n, p);
  /* Derivatives above the degree vanish; A2.3 only computes up to p. */
  int nd = p < BSPLINE_MAX_DERIV ? p : BSPLINE_MAX_DERIV;
  double ders[BSPLINE_MAX_DERIV + 1][BSPLINE_MAX_DEGREE + 1];
  basis_derivatives(t, span, n, p, nd, ders);
  for (int k = 0; k <= BSPLINE_MAX_DERIV; k++) {
    if (!out[k])
      continue;
    for (int c = 0; c < dim; c++) {
      double sum = 0.0;
      for (int j = 0; j <= p; j++)
        sum += ders[k][j] * (double)ctrl[(span - p + j) * dim + c];
      out[k][c] = sum;
    }
  }
}
