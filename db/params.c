/* params.c - the parameters a database is built with and the geometry of
 * its records: they belong to the database's contract (a renderer needs them
 * to lay records across its shells), so they live here rather than in the
 * offline tracer. */
#include <math.h>

#include "satf/db.h"
#include "satf/math.h"

satf_sector_shape satf_sector_shape_default(void) {
  satf_sector_shape s = {0.8f, 1.0f, 2.0f * SATF_PI_F / 16.0f};
  return s;
}

satf_status satf_sector_shape_check(const satf_sector_shape *s,
                                    satf_error *err) {
  if (!(s->r_inner > 0.0f) || !(s->r_outer > s->r_inner) ||
      !(s->r_outer < 1e6f))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "sector radii must satisfy 0 < r_inner (%g) < "
                          "r_outer (%g)",
                          (double)s->r_inner, (double)s->r_outer);
  if (!(s->phase_span > 0.0f) || !(s->phase_span <= SATF_PI_F))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "sector phase span %g must be in (0, pi]",
                          (double)s->phase_span);
  return SATF_OK;
}

satf_trace_params satf_trace_params_default(void) {
  satf_trace_params p;
  p.width = 32;
  /* A layer of a 15-layer cluster is about 1.5 strand diameters deep, so a
   * ray crossing it at coverage 1 meets about two strands: extinction 10
   * over the canonical depth 0.2 gives that optical depth of 2. */
  p.extinction = 10.0f;
  p.ambient = 0.08f;
  p.diffuse = 0.7f;
  p.specular = 0.35f;
  p.shininess = 24.0f;
  p.epsilon = 1e-3f;
  p.self_shadow = 1;
  p.smooth_ratio = 1.5f;
  return p;
}

satf_status satf_trace_params_check(const satf_trace_params *p,
                                    satf_error *err) {
#define RANGE(field, lo, hi)                                                   \
  if (!((double)p->field >= (lo) && (double)p->field <= (hi)))                 \
    return satf_error_set(err, SATF_ERR_ARGUMENT,                              \
                          #field " = %g is out of range [%g, %g]",             \
                          (double)p->field, (double)(lo), (double)(hi));
  RANGE(width, 2, 4096)
  RANGE(extinction, 0.0, 1e6)
  RANGE(ambient, 0.0, 10.0)
  RANGE(diffuse, 0.0, 10.0)
  RANGE(specular, 0.0, 10.0)
  RANGE(shininess, 0.0, 10000.0)
  RANGE(epsilon, 1e-9, 0.5)
  RANGE(self_shadow, 0, 1)
  RANGE(smooth_ratio, 0.0, 100.0)
#undef RANGE
  return SATF_OK;
}

/* Extent of the annular sector projected on unit axis e: the extremes of a
 * linear function over the region lie at its corners or where an arc's
 * tangent is perpendicular to e. */
void satf_sector_extent(const satf_sector_shape *sh, const float e[2],
                        float *lo, float *hi) {
  float half = 0.5f * sh->phase_span;
  float radii[2] = {sh->r_inner, sh->r_outer};
  float phis[4] = {-half, half, atan2f(e[1], e[0]), 0.0f};
  phis[3] = phis[2] > 0.0f ? phis[2] - SATF_TWO_PI_F * 0.5f
                           : phis[2] + SATF_TWO_PI_F * 0.5f;
  float mn = INFINITY, mx = -INFINITY;
  for (int r = 0; r < 2; r++) {
    for (int k = 0; k < 4; k++) {
      if (k >= 2 && fabsf(phis[k]) > half)
        continue;
      float v = radii[r] * (cosf(phis[k]) * e[0] + sinf(phis[k]) * e[1]);
      mn = v < mn ? v : mn;
      mx = v > mx ? v : mx;
    }
  }
  *lo = mn;
  *hi = mx;
}

void satf_trace_extent(const satf_sector_shape *shape, float theta_v,
                       float *pmin, float *pmax) {
  float e[2] = {-sinf(theta_v), cosf(theta_v)};
  satf_sector_extent(shape, e, pmin, pmax);
}
