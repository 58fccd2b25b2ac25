/* record_kind.c - the record kinds of a database (satf/db.h "Record kinds"):
 * the build parameters' defaults, the fibre tracer's parameters with their
 * defaults and checks, and what a kind means for a record's channels and
 * the file's format version. */
#include <math.h>
#include <string.h>

#include "satf/db.h"
#include "satf/fiber.h"
#include "satf/math.h"

satf_build_params satf_build_params_default(void) {
  satf_build_params p;
  memset(&p, 0, sizeof p);
  p.seed = 1;
  p.samples = 256;
  p.n_view = 32;
  p.n_light = 32;
  p.grid = 32;
  p.shape = satf_sector_shape_default();
  p.trace = satf_trace_params_default();
  p.kind = SATF_RECORD_PHONG;
  p.fiber = satf_fiber_trace_params_default(); /* for --kind fiber */
  return p;
}

satf_fiber_trace_params satf_fiber_trace_params_default(void) {
  satf_fiber_trace_params p;
  memset(&p, 0, sizeof p);
  p.eta = 1.55f;   /* Marschner 2003, Cycles and pbrt default */
  p.beta_n = 0.3f; /* Cycles' Radial Roughness default */
  /* Absorption levels per unit fibre radius: Cycles' melanin 0 .. 1 spans
   * sigma_a 0 .. ~15 (blue of black hair). Measured with
   * tests/offline/bench_fiber_levels: log-linear interpolation in
   * sigma between these levels stays within 2.7% (TT), 3.6% (TRT) and 6.4%
   * (MS, near sigma 0.1) of traced values over sigma in [0.1, 16]. */
  p.levels = 5;
  p.sigma_a[0] = 0.0f;
  p.sigma_a[1] = 0.2f;
  p.sigma_a[2] = 1.0f;
  p.sigma_a[3] = 4.0f;
  p.sigma_a[4] = 16.0f;
  p.sub_rays = 24;
  p.max_bounces = 64;
  return p;
}

satf_status satf_fiber_trace_params_check(const satf_fiber_trace_params *p,
                                          satf_error *err) {
  if (!(p->eta > 1.0f && p->eta < 4.0f))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "fibre eta = %g is out of range (1, 4)",
                          (double)p->eta);
  if (!(p->beta_n > 0.0f && p->beta_n <= 1.0f))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "radial roughness beta_n = %g is out of range "
                          "(0, 1]",
                          (double)p->beta_n);
  if (p->levels < 1 || p->levels > SATF_DB_LEVELS_MAX)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "absorption levels = %d is out of range [1, %d]",
                          p->levels, SATF_DB_LEVELS_MAX);
  for (int k = 0; k < p->levels; k++) {
    float s = p->sigma_a[k];
    if (!(s >= 0.0f && s <= 1000.0f) || (k > 0 && !(s > p->sigma_a[k - 1])))
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "absorption level %d (sigma_a = %g) must be in "
                            "[0, 1000] and above the previous level",
                            k, (double)s);
  }
  if (p->sub_rays < 1 || p->sub_rays > 65536)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "sub-rays = %d is out of range [1, 65536]",
                          p->sub_rays);
  if (p->max_bounces < 1 || p->max_bounces > 10000)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "max bounces = %d is out of range [1, 10000]",
                          p->max_bounces);
  return SATF_OK;
}

const char *satf_record_kind_name(satf_record_kind kind) {
  return kind == SATF_RECORD_FIBER ? "fiber" : "phong";
}

int satf_record_kind_parse(const char *name, satf_record_kind *kind) {
  if (strcmp(name, "phong") == 0)
    *kind = SATF_RECORD_PHONG;
  else if (strcmp(name, "fiber") == 0)
    *kind = SATF_RECORD_FIBER;
  else
    return -1;
  return 0;
}

satf_build_params satf_build_params_default_fiber(void) {
  satf_build_params p = satf_build_params_default();
  p.kind = SATF_RECORD_FIBER;
  p.fiber = satf_fiber_trace_params_default();
  /* A record keeps 3 + 3 levels channels instead of 2: narrower records
   * and fewer samples keep the default file near 30 MB and its reading
   * near 2.5 s of CPU (measured). */
  p.trace.width = 16;
  p.samples = 128;
  return p;
}

int satf_build_params_channels(const satf_build_params *p) {
  return p->kind == SATF_RECORD_FIBER ? SATF_DB_FIBER_CHANNELS(p->fiber.levels)
                                      : 2;
}

int satf_build_params_version(const satf_build_params *p) {
  return p->kind == SATF_RECORD_FIBER ? 2 : 1;
}

int satf_fiber_trace_min_lights(float beta_n) {
  /* The lights' Riemann sum of a trimmed logistic of scale s errs by
   * 3.6e-4 at spacing 1.68 s (beta_n 0.3, 32 lights) and by 4.5% at 3.1 s
   * (beta_n 0.2, 32 lights): keep the spacing at or below 1.7 s. */
  float s = satf_fiber_azimuthal_scale(beta_n);
  if (!(s > 0.0f))
    return 1 << 30;
  return (int)ceilf(SATF_TWO_PI_F / (1.7f * s));
}
