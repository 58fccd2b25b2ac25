/* test_fiber_slab.c - dual scattering (Zinke et al. 2008) against a path
 * traced reference worked out independently of it: a semi-infinite slab of
 * parallel fibres (along x, lying in the surface z = 0, the hair in z < 0)
 * as a medium whose extinction for a ray of direction d is
 * sqrt(1 - d_x^2) per unit length (a fibre's projected width), each
 * collision at a uniform offset h scattering by the fibre model, sampled
 * lobe by lobe as pbrt-v4's HairBxDF::Sample_f (M_p by d'Eon's inverse
 * CDF, N_p by the trimmed logistic's), the light by next-event estimation.
 * What reaches the eye ray's first fibre from the hair behind it (the
 * sampled direction pointing out of the slab) is the local
 * back-scattering that d_b f_back models there; the test compares the two
 * with d_b = 1 (the slab surrounds its surface fibres from behind). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>

#include "satf/fiber.h"
#include "satf/math.h"
#include "test_util.h"

#define NT 32

static double uniform(uint64_t *x) {
  *x ^= *x << 13;
  *x ^= *x >> 7;
  *x ^= *x << 17;
  return ((double)(*x >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

static void unit_dir(double theta, double phi, float w[3]) {
  w[0] = (float)sin(theta);
  w[1] = (float)(cos(theta) * sin(phi));
  w[2] = (float)(cos(theta) * cos(phi));
}

/* Samples wi for wo at offset h (lobe p with probability ~ A_p, then M_p
 * and N_p exactly); returns f / pdf per channel in w. */
static void sample_fiber(const satf_fiber *f, const float wo[3], float h,
                         uint64_t *rng, float wi[3], double w[3]) {
  float so = wo[0], co = sqrtf(fmaxf(1.0f - so * so, 0.0f));
  double q[SATF_FIBER_LOBES] = {0}, qs = 0;
  for (int c = 0; c < 3; c++) {
    float ap[SATF_FIBER_LOBES];
    satf_fiber_ap(co, f->eta, h,
                  satf_fiber_transmittance(f->sigma_a[c], h, f->eta, so), ap);
    for (int p = 0; p < SATF_FIBER_LOBES; p++)
      q[p] += ap[p];
  }
  for (int p = 0; p < SATF_FIBER_LOBES; p++)
    qs += q[p];
  for (int p = 0; p < SATF_FIBER_LOBES; p++)
    q[p] /= qs;
  double u = uniform(rng);
  int p = 0;
  while (p < SATF_FIBER_LOBES - 1 && u > q[p])
    u -= q[p++];
  float sp, cp;
  satf_fiber_tilt(f, p, so, co, &sp, &cp);
  double v = f->v[p], u0 = uniform(rng);
  double ct = 1.0 + v * log(u0 + (1.0 - u0) * exp(-2.0 / v));
  double st = sqrt(fmax(1.0 - ct * ct, 0.0));
  double si = -ct * sp + st * cos(2.0 * SATF_PI * uniform(rng)) * cp;
  si = fmax(fmin(si, 1.0), -1.0);
  double ci = sqrt(1.0 - si * si);
  float go = asinf(h), gt = asinf(h / satf_fiber_eta_prime(f->eta, so));
  double dphi =
      p < 3 ? satf_fiber_phi(p, go, gt) +
                  satf_fiber_sample_trimmed_logistic((float)uniform(rng), f->s)
            : 2.0 * SATF_PI * uniform(rng);
  double phi = atan2(wo[2], wo[1]) + dphi;
  wi[0] = (float)si;
  wi[1] = (float)(ci * cos(phi));
  wi[2] = (float)(ci * sin(phi));
  /* the mixture's pdf at wi */
  double pdf = 0;
  float ci_f = (float)ci, si_f = (float)si;
  float rel = atan2f(wi[2], wi[1]) - atan2f(wo[2], wo[1]);
  for (int l = 0; l < SATF_FIBER_LOBES; l++) {
    satf_fiber_tilt(f, l, so, co, &sp, &cp);
    double np = l < 3 ? satf_fiber_np(rel, l, f->s, go, gt) : 0.5 / SATF_PI;
    pdf += q[l] * satf_fiber_mp(ci_f, cp, si_f, sp, f->v[l]) * np;
  }
  float fv[3];
  satf_fiber_eval(f, wo, wi, h, fv);
  for (int c = 0; c < 3; c++)
    w[c] = pdf > 0 ? fv[c] / pdf : 0.0;
}

/* Luminance of what reaches the eye's first fibre from behind (path traced)
 * and of d_b f_back there (dual scattering, d_b = 1), both over the direct
 * single scattering e^-n f_s, for light and eye at the given directions. */
static void slab(float melanin, const float wl[3], const float we[3], int paths,
                 double *traced, double *dual) {
  satf_fiber_material m = satf_fiber_material_default();
  m.melanin = melanin;
  satf_fiber f;
  satf_fiber_init(&f, &m);
  float tab[NT * SATF_FIBER_DUAL_FIELDS * 3];
  satf_fiber_dual_tables(&f, NT, tab);
  const double Y[3] = {0.2126, 0.7152, 0.0722};
  double single = 0, behind = 0, back = 0;
  double ext_l = sqrt(1.0 - wl[0] * wl[0]);
  uint64_t rng = 0x9E3779B97F4A7C15ull;
  for (int i = 0; i < paths; i++) {
    float d[3] = {-we[0], -we[1], -we[2]};
    double z = 0, thr[3] = {1, 1, 1};
    int from_behind = 0;
    for (int k = 0; k < 200; k++) {
      z += d[2] * -log(uniform(&rng)) / sqrt(fmax(1.0 - d[0] * d[0], 1e-8));
      if (z > 0)
        break;
      float wo[3] = {-d[0], -d[1], -d[2]};
      float h = (float)(2.0 * uniform(&rng) - 1.0);
      double n = ext_l * -z / wl[2]; /* hairs between the point and light */
      float fs[3];
      satf_fiber_eval(&f, wo, wl, h, fs);
      for (int c = 0; c < 3; c++) {
        double L = thr[c] * fs[c] * exp(-n);
        if (k == 0)
          single += Y[c] * L;
        else if (from_behind)
          behind += Y[c] * L;
      }
      if (k == 0) {
        float lit[3];
        satf_fiber_dual_shade(&f, tab, NT, wo, wl, h, 0.0f, lit);
        for (int c = 0; c < 3; c++)
          back += Y[c] * (lit[c] - fs[c]) * exp(-n) / SATF_FIBER_DUAL_DENSITY;
      }
      float wi[3];
      double w[3];
      sample_fiber(&f, wo, h, &rng, wi, w);
      if (k == 0)
        from_behind = wi[2] < 0; /* the light comes up from deeper hair */
      double mx = 0;
      for (int c = 0; c < 3; c++) {
        thr[c] *= w[c];
        mx = fmax(mx, thr[c]);
      }
      d[0] = wi[0];
      d[1] = wi[1];
      d[2] = wi[2];
      if (mx < 1e-4)
        break;
    }
  }
  *traced = behind / single;
  *dual = back / single;
}

/* Dark (melanin 0.6) and blond (0.2) hair, the light 20 degrees along the
 * fibres and 30 across, the eye along the slab's normal: the local
 * back-scattering within 30% of the traced one (measured +14% and -18%).
 * Zinke's own sums (eq. 11, 13, with eq. 6 and 12's fractions taken per
 * arriving ray) gave 0.30 of it for the dark hair. */
static void local_back_scattering_matches_traced(void **state) {
  (void)state;
  float wl[3], we[3];
  unit_dir(20.0 * SATF_PI / 180.0, 30.0 * SATF_PI / 180.0, wl);
  unit_dir(0.0, 0.0, we);
  const float melanins[] = {0.6f, 0.2f};
  for (int i = 0; i < 2; i++) {
    double traced, dual;
    slab(melanins[i], wl, we, 20000, &traced, &dual);
    print_message("melanin %.1f: from behind / single: traced %.3f, dual "
                  "scattering %.3f\n",
                  melanins[i], traced, dual);
    assert_near(dual, traced, 0.3 * traced);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(local_back_scattering_matches_traced),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
