/* fiber_dual.c - the precomputed tables of the dual scattering
 * approximation (Zinke et al. 2008, paper 004) from the fibre model of
 * fiber.c, and the local back-scattering BCSDF they give. */
#include <math.h>
#include <stddef.h>

#include "satf/fiber.h"
#include "satf/math.h"

/* Quadrature points over h for the azimuthal averages. */
#define DUAL_NH 256

/* The lobe's mean shift of theta_i + theta_o (satf_fiber_tilt's
 * convention). */
static float lobe_shift(const satf_fiber *f, int p) {
  switch (p) {
  case 0: return -2.0f * f->alpha;
  case 1: return f->alpha;
  case 2: return 4.0f * f->alpha;
  default: return 0.0f;
  }
}

/* Forward and backward fractions of each lobe for light at |theta|, one
 * channel, averaged over the fibre's width. */
static void lobe_fractions(const satf_fiber *f, float theta, int c,
                           double fwd[SATF_FIBER_LOBES],
                           double bwd[SATF_FIBER_LOBES]) {
  float sin_t = sinf(theta), cos_t = cosf(theta);
  float etap = satf_fiber_eta_prime(f->eta, sin_t);
  for (int p = 0; p < SATF_FIBER_LOBES; p++)
    fwd[p] = bwd[p] = 0.0;
  for (int j = 0; j < DUAL_NH; j++) {
    float h = -1.0f + 2.0f * ((float)j + 0.5f) / DUAL_NH;
    float T = satf_fiber_transmittance(f->sigma_a[c], h, f->eta, sin_t);
    float ap[SATF_FIBER_LOBES];
    satf_fiber_ap(cos_t, f->eta, h, T, ap);
    float gamma_o = asinf(h), gamma_t = asinf(h / etap);
    for (int p = 0; p < SATF_FIBER_LOBES; p++) {
      /* backward: the exit azimuth within pi / 2 of the light's */
      float back =
          p < 3 ? satf_fiber_np_integral(-0.5f * SATF_PI_F, 0.5f * SATF_PI_F, p,
                                         f->s, gamma_o, gamma_t)
                : 0.5f;
      bwd[p] += (double)ap[p] * back / DUAL_NH;
      fwd[p] += (double)ap[p] * (1.0f - back) / DUAL_NH;
    }
  }
}

void satf_fiber_dual_tables(const satf_fiber *f, int n, float *out) {
  for (int k = 0; k < n; k++) {
    float theta = ((float)k + 0.5f) / (float)n * 0.5f * SATF_PI_F;
    for (int c = 0; c < 3; c++) {
      double fwd[SATF_FIBER_LOBES], bwd[SATF_FIBER_LOBES];
      lobe_fractions(f, theta, c, fwd, bwd);
      double af = 0, ab = 0, alf = 0, alb = 0, bf = 0, bb = 0;
      for (int p = 0; p < SATF_FIBER_LOBES; p++) {
        af += fwd[p];
        ab += bwd[p];
        alf += fwd[p] * lobe_shift(f, p);
        alb += bwd[p] * lobe_shift(f, p);
        bf += fwd[p] * f->v[p];
        bb += bwd[p] * f->v[p];
      }
      /* energy-weighted means of the lobes' shifts and variances */
      alf = af > 0 ? alf / af : 0;
      alb = ab > 0 ? alb / ab : 0;
      bf = af > 0 ? bf / af : f->v[1];
      bb = ab > 0 ? bb / ab : f->v[0];
      double af2 = af * af, ab2 = ab * ab, ab3 = ab2 * ab;
      double one = 1.0 - af2 > 1e-6 ? 1.0 - af2 : 1e-6;
      double A1 = ab * af2 / one;                /* eq. 11 */
      double A3 = ab3 * af2 / (one * one * one); /* eq. 13 */
      double Ab = A1 + A3;                       /* eq. 14 */
      double delta = alb * (1.0 - 2.0 * ab2 / (one * one)) +
                     alf * (2.0 * one * one + 4.0 * af2 * ab2) /
                         (one * one * one); /* eq. 16 */
      double sf = sqrt(bf), sb = sqrt(bb);
      double den = ab + ab3 * (2.0 * sf + 3.0 * sb);
      double sigma = den > 0 ? (1.0 + SATF_FIBER_DUAL_DENSITY * af2) *
                                   (ab * sqrt(2.0 * bf + bb) +
                                    ab3 * sqrt(2.0 * bf + 3.0 * bb)) /
                                   den
                             : sb; /* eq. 17 */
      float *o = out + (size_t)k * SATF_FIBER_DUAL_FIELDS * 3 + c;
      o[3 * SATF_FIBER_DUAL_AF] = (float)af;
      o[3 * SATF_FIBER_DUAL_AB] = (float)ab;
      o[3 * SATF_FIBER_DUAL_ALPHA_F] = (float)alf;
      o[3 * SATF_FIBER_DUAL_ALPHA_B] = (float)alb;
      o[3 * SATF_FIBER_DUAL_BETA_F2] = (float)bf;
      o[3 * SATF_FIBER_DUAL_BETA_B2] = (float)bb;
      o[3 * SATF_FIBER_DUAL_A_B] = (float)Ab;
      o[3 * SATF_FIBER_DUAL_DELTA_B] = (float)delta;
      o[3 * SATF_FIBER_DUAL_SIGMA_B2] = (float)(sigma * sigma);
    }
  }
}

float satf_fiber_dual_lookup(const float *tables, int n, int field, int c,
                             float theta) {
  float x = fabsf(theta) / (0.5f * SATF_PI_F) * (float)n - 0.5f;
  if (x < 0.0f)
    x = 0.0f;
  if (x > (float)(n - 1))
    x = (float)(n - 1);
  int k = (int)x;
  if (k > n - 2)
    k = n > 1 ? n - 2 : 0;
  float t = n > 1 ? x - (float)k : 0.0f;
  float a = tables[((size_t)k * SATF_FIBER_DUAL_FIELDS + field) * 3 + c];
  float b =
      n > 1 ? tables[((size_t)(k + 1) * SATF_FIBER_DUAL_FIELDS + field) * 3 + c]
            : a;
  return a + t * (b - a);
}

float satf_fiber_dual_back(const float *tables, int n, int c, const float wo[3],
                           const float wi[3], float extra_var) {
  float dphi = atan2f(wi[2], wi[1]) - atan2f(wo[2], wo[1]);
  dphi = fabsf(remainderf(dphi, SATF_TWO_PI_F));
  if (dphi >= 0.5f * SATF_PI_F)
    return 0.0f; /* forward: no local back-scattering */
  float to = asinf(fminf(fmaxf(wo[0], -1.0f), 1.0f));
  float ti = asinf(fminf(fmaxf(wi[0], -1.0f), 1.0f));
  float theta_d = 0.5f * (to - ti);
  float Ab = satf_fiber_dual_lookup(tables, n, SATF_FIBER_DUAL_A_B, c, theta_d);
  float delta =
      satf_fiber_dual_lookup(tables, n, SATF_FIBER_DUAL_DELTA_B, c, theta_d);
  float var =
      satf_fiber_dual_lookup(tables, n, SATF_FIBER_DUAL_SIGMA_B2, c, theta_d) +
      extra_var;
  var = fmaxf(var, 1e-4f);
  /* Zinke's Gaussian g(theta_i + theta_o - Delta_b, var) / cos(theta_d)
   * as d'Eon's M_p of that variance around theta_o - Delta_b: the same
   * for narrow lobes, and normalised on the sphere for the wide ones
   * (sigma_b reaches 0.8 rad for blond hair), so f_back integrates to A_b */
  float tc = to - delta;
  float mp = satf_fiber_mp(cosf(ti), fabsf(cosf(tc)), sinf(ti), sinf(tc), var);
  return Ab * mp / SATF_PI_F;
}

void satf_fiber_dual_shade(const satf_fiber *f, const float *tables, int n,
                           const float wo[3], const float wi[3], float h,
                           float n_hairs, float out[3]) {
  float single[SATF_FIBER_LOBES][3];
  satf_fiber_eval_lobes(f, wo, wi, h, single);
  h = fminf(fmaxf(h, -1.0f), 1.0f);
  float sin_o = fminf(fmaxf(wo[0], -1.0f), 1.0f);
  float cos_o = sqrtf(fmaxf(1.0f - sin_o * sin_o, 0.0f));
  float theta_o = asinf(sin_o), phi_o = atan2f(wo[2], wo[1]);
  float sin_i = fminf(fmaxf(wi[0], -1.0f), 1.0f);
  float theta_i = asinf(sin_i), cos_i = cosf(theta_i);
  float phi_i = atan2f(wi[2], wi[1]);
  float gamma_o = asinf(h);
  float gamma_t =
      asinf(fminf(fmaxf(h / satf_fiber_eta_prime(f->eta, sin_o), -1.0f), 1.0f));
  float nh = fmaxf(n_hairs, 0.0f);
  float direct = expf(-nh);
  float dphi = fabsf(remainderf(phi_i - phi_o, SATF_TWO_PI_F));
  float theta_d = 0.5f * (theta_o - theta_i);
  float ng[SATF_FIBER_LOBES];
  for (int p = 0; p < SATF_FIBER_LOBES; p++)
    ng[p] = p < 3 ? satf_fiber_np_integral(phi_i - 0.5f * SATF_PI_F - phi_o,
                                           phi_i + 0.5f * SATF_PI_F - phi_o, p,
                                           f->s, gamma_o, gamma_t) /
                        SATF_PI_F
                  : 0.5f / SATF_PI_F;
  for (int c = 0; c < 3; c++) {
    float af =
        satf_fiber_dual_lookup(tables, n, SATF_FIBER_DUAL_AF, c, theta_i);
    float bf2 =
        satf_fiber_dual_lookup(tables, n, SATF_FIBER_DUAL_BETA_F2, c, theta_i);
    float scattered = fmaxf(expf(-nh * (1.0f - af)) - direct, 0.0f);
    float sf2 = fmaxf(nh, 1.0f) * bf2;
    float ab =
        satf_fiber_dual_lookup(tables, n, SATF_FIBER_DUAL_A_B, c, theta_d);
    float delta =
        satf_fiber_dual_lookup(tables, n, SATF_FIBER_DUAL_DELTA_B, c, theta_d);
    float v = fmaxf(
        satf_fiber_dual_lookup(tables, n, SATF_FIBER_DUAL_SIGMA_B2, c, theta_d),
        1e-4f);
    float tc = theta_o - delta;
    float back =
        dphi < 0.5f * SATF_PI_F
            ? ab * satf_fiber_mp(cos_i, fabsf(cosf(tc)), sin_i, sinf(tc), v) /
                  SATF_PI_F
            : 0.0f;
    float back_g =
        ab * satf_fiber_mp(cos_i, fabsf(cosf(tc)), sin_i, sinf(tc), v + sf2) *
        (SATF_PI_F - dphi) / (SATF_PI_F * SATF_PI_F);
    float s = 0.0f, sg = 0.0f;
    float ap[SATF_FIBER_LOBES];
    satf_fiber_ap(cos_o, f->eta, h,
                  satf_fiber_transmittance(f->sigma_a[c], h, f->eta, sin_o),
                  ap);
    for (int p = 0; p < SATF_FIBER_LOBES; p++) {
      float sp, cp;
      satf_fiber_tilt(f, p, sin_o, cos_o, &sp, &cp);
      s += single[p][c];
      sg += satf_fiber_mp(cos_i, cp, sin_i, sp, f->v[p] + sf2) * ng[p] * ap[p];
    }
    out[c] = direct * (s + SATF_FIBER_DUAL_DENSITY * back) +
             SATF_FIBER_DUAL_DENSITY * scattered *
                 (sg + SATF_FIBER_DUAL_DENSITY * back_g);
  }
}
