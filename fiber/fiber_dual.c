/* fiber_dual.c - the precomputed tables of the dual scattering
 * approximation (Zinke et al. 2008, paper 004) from the fibre model of
 * fiber.c, and the local back-scattering BCSDF they give. */
#include <math.h>
#include <stddef.h>

#include "satf/common.h"
#include "satf/fiber.h"
#include "satf/math.h"

/* Quadrature points over h for the azimuthal averages. */
#define DUAL_NH 128

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

/* Incident azimuths (relative to the shadow path) over which eq. 6 and
 * 12 average. With 128 offsets h, a_b and A_b are within 0.8% of 256 x 32
 * points for beta_n 0.1-0.8 and melanin 0-0.9, at 5x the cost of the
 * per-ray fractions (0.2 s for 32 rows on a loaded core; once per
 * material, fiber_gpu.c). */
#define DUAL_NPSI 16

/* Forward and backward fractions of each lobe for light at |theta|, one
 * channel, averaged over the fibre's width: Zinke's eq. 6 and 12, the
 * light arriving isotropically over the half-circle of azimuths around the
 * shadow path (his "isotropic irradiance along the specular cone", the
 * forward-scattered light of eq. 7), and the exit split into the half of
 * the normal plane that goes on along the path (forward) and the half that
 * returns (backward), both fixed by the path, not by each arriving ray. */
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
      double back = 0.0;
      for (int q = 0; q < DUAL_NPSI; q++) {
        /* the path's returning half-circle seen from a ray arriving psi
         * off the path: the exit azimuth within pi / 2 of psi */
        float psi = SATF_PI_F * (((float)q + 0.5f) / DUAL_NPSI - 0.5f);
        back += p < 3 ? satf_fiber_np_integral(psi - 0.5f * SATF_PI_F,
                                               psi + 0.5f * SATF_PI_F, p, f->s,
                                               gamma_o, gamma_t)
                      : 0.5;
      }
      back /= DUAL_NPSI;
      bwd[p] += (double)ap[p] * back / DUAL_NH;
      fwd[p] += (double)ap[p] * (1.0 - back) / DUAL_NH;
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
      /* Local back-scattering with hair crossings counted as a Poisson
       * process, the model of the global term (satf_fiber_dual_shade's
       * e^-n(1 - a_f)): over a path of m expected crossings the light keeps
       * e^-m(1 - a_f) (it passes between hairs or is forward-scattered),
       * each crossing returns a_b, and the point's own fibre forward-
       * scatters the returned light once (a_f). One backward event at depth
       * m (eq. 11's paths): a_b int_0^inf e^-2cm dm a_f = a_f a_b / (2c),
       * c = 1 - a_f; three (eq. 13's: back at m1, m2 < m1, m3 > m2):
       * a_f a_b^3 / (8 c^3). Zinke's sums count a_f^2i, a scattering at
       * every hair crossed both ways, which leaves out the light that
       * reaches a hair unscattered (for a_f -> 1 both give a_b / 2c and
       * a_b^3 / 8c^3). */
      double c1 = 1.0 - af > 1e-3 ? 1.0 - af : 1e-3;
      double A1 = af * ab / (2.0 * c1);
      double A3 = af * ab * ab * ab / (8.0 * c1 * c1 * c1);
      double Ab = A1 + A3;
      /* the forward events' expected counts on those paths: the point's own
       * plus a_f per crossing over the mean path length 1 / c (three back
       * events: 3 / c) */
      double n1 = 1.0 + af / c1, n3 = 1.0 + 3.0 * af / c1;
      double d1 = alb + n1 * alf, d3 = 3.0 * alb + n3 * alf;
      double v1 = bb + n1 * bf, v3 = 3.0 * bb + n3 * bf;
      double w1 = Ab > 0 ? A1 / Ab : 1.0, w3 = 1.0 - w1;
      double delta = w1 * d1 + w3 * d3;
      /* the mixture's variance */
      double var = w1 * (v1 + d1 * d1) + w3 * (v3 + d3 * d3) - delta * delta;
      double sigma = sqrt(var > 1e-6 ? var : 1e-6);
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

void satf_fiber_dual_global(const satf_fiber *f, const float *tables, int n,
                            const float wo[3], const float wi[3], float h,
                            float n_hairs, float global[3], float back[3]) {
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
    float bf2 =
        satf_fiber_dual_lookup(tables, n, SATF_FIBER_DUAL_BETA_F2, c, theta_i);
    float sf2 = fmaxf(nh, 1.0f) * bf2;
    float ab =
        satf_fiber_dual_lookup(tables, n, SATF_FIBER_DUAL_A_B, c, theta_d);
    float delta =
        satf_fiber_dual_lookup(tables, n, SATF_FIBER_DUAL_DELTA_B, c, theta_d);
    float v = fmaxf(
        satf_fiber_dual_lookup(tables, n, SATF_FIBER_DUAL_SIGMA_B2, c, theta_d),
        1e-4f);
    float tc = theta_o - delta;
    back[c] =
        dphi < 0.5f * SATF_PI_F
            ? ab * satf_fiber_mp(cos_i, fabsf(cosf(tc)), sin_i, sinf(tc), v) /
                  SATF_PI_F
            : 0.0f;
    float back_g =
        ab * satf_fiber_mp(cos_i, fabsf(cosf(tc)), sin_i, sinf(tc), v + sf2) *
        (SATF_PI_F - dphi) / (SATF_PI_F * SATF_PI_F);
    float sg = 0.0f;
    float ap[SATF_FIBER_LOBES];
    satf_fiber_ap(cos_o, f->eta, h,
                  satf_fiber_transmittance(f->sigma_a[c], h, f->eta, sin_o),
                  ap);
    for (int p = 0; p < SATF_FIBER_LOBES; p++) {
      float sp, cp;
      satf_fiber_tilt(f, p, sin_o, cos_o, &sp, &cp);
      sg += satf_fiber_mp(cos_i, cp, sin_i, sp, f->v[p] + sf2) * ng[p] * ap[p];
    }
    global[c] =
        SATF_FIBER_DUAL_DENSITY * (sg + SATF_FIBER_DUAL_DENSITY * back_g);
  }
}

void satf_fiber_dual_shade(const satf_fiber *f, const float *tables, int n,
                           const float wo[3], const float wi[3], float h,
                           float n_hairs, float out[3]) {
  satf_fiber_dual_shade_behind(f, tables, n, wo, wi, h, n_hairs, INFINITY, out);
}

void satf_fiber_dual_shade_behind(const satf_fiber *f, const float *tables,
                                  int n, const float wo[3], const float wi[3],
                                  float h, float n_hairs, float n_behind,
                                  float out[3]) {
  /* Zinke's d_b (eq. 9) scaled by the hairs behind the point that send
   * the local back-scattering (strand_fiber.glsl says why) */
  float d_b = SATF_FIBER_DUAL_DENSITY * (1.0f - expf(-fmaxf(n_behind, 0.0f)));
  float single[SATF_FIBER_LOBES][3], global[3], back[3];
  satf_fiber_eval_lobes(f, wo, wi, h, single);
  satf_fiber_dual_global(f, tables, n, wo, wi, h, n_hairs, global, back);
  float nh = fmaxf(n_hairs, 0.0f), direct = expf(-nh);
  float theta_i = asinf(fminf(fmaxf(wi[0], -1.0f), 1.0f));
  for (int c = 0; c < 3; c++) {
    float af =
        satf_fiber_dual_lookup(tables, n, SATF_FIBER_DUAL_AF, c, theta_i);
    float scattered = fmaxf(expf(-nh * (1.0f - af)) - direct, 0.0f);
    float s = 0.0f;
    for (int p = 0; p < SATF_FIBER_LOBES; p++)
      s += single[p][c];
    out[c] = direct * (s + d_b * back[c]) + scattered * global[c];
  }
}

/* The warp of satf_fiber_global_coords: x in [-range, range] to
 * 1/2 + asinh(x / w) / (2 asinh(range / w)), and its inverse from such a
 * coordinate. */
static float warp(float x, float w, float range) {
  return 0.5f + 0.5f * asinhf(x / w) / asinhf(range / w);
}
static float unwarp(float u, float w, float range) {
  return w * sinhf((2.0f * u - 1.0f) * asinhf(range / w));
}

/* The warps' scales: TT's longitudinal deviation in theta_h (half that in
 * theta_i + theta_o), the narrowest lobe's; twice the logistic scale. */
static float scale_h(const satf_fiber *f) {
  return fmaxf(0.5f * sqrtf(f->v[1]), 0.02f);
}

void satf_fiber_global_coords(const satf_fiber *f, float theta_o, float theta_i,
                              float phi, float out[3]) {
  const float half_pi = 0.5f * SATF_PI_F;
  out[0] = warp(0.5f * (theta_o + theta_i), scale_h(f), half_pi);
  out[1] = 0.5f + (theta_o - theta_i) / (2.0f * SATF_PI_F);
  out[2] = warp(fabsf(phi) - half_pi, 2.0f * f->s, half_pi);
}

typedef struct global_job {
  const satf_fiber *f;
  const float *tables;
  int n;
  float *global, *back;
} global_job;

/* One phi bin of the table: NH x ND entries. */
static int global_slice(void *ctx, size_t kp, int thread) {
  (void)thread;
  const global_job *j = ctx;
  const satf_fiber *f = j->f;
  const float half_pi = 0.5f * SATF_PI_F;
  const int nh = SATF_FIBER_GLOBAL_NH, nd = SATF_FIBER_GLOBAL_ND;
  /* the bins' centres, unwarped */
  float phi = half_pi + unwarp(((float)kp + 0.5f) / SATF_FIBER_GLOBAL_NPHI,
                               2.0f * f->s, half_pi);
  size_t at = kp * (size_t)nh * (size_t)nd * 3;
  for (int kd = 0; kd < nd; kd++) {
    float td = SATF_PI_F * (((float)kd + 0.5f) / (float)nd - 0.5f);
    for (int kh = 0; kh < nh; kh++, at += 3) {
      float th = unwarp(((float)kh + 0.5f) / (float)nh, scale_h(f), half_pi);
      /* cells past the sphere's angles (|theta| > pi / 2) take its edge:
       * only filtering next to it reads them */
      float to = fminf(fmaxf(th + td, -half_pi), half_pi);
      float ti = fminf(fmaxf(th - td, -half_pi), half_pi);
      float wo[3] = {sinf(to), cosf(to), 0.0f};
      float wi[3] = {sinf(ti), cosf(ti) * cosf(phi), cosf(ti) * sinf(phi)};
      satf_fiber_dual_global(f, j->tables, j->n, wo, wi, 0.0f, 1.0f,
                             j->global + at, j->back + at);
    }
  }
  return 0;
}

void satf_fiber_dual_global_table(const satf_fiber *f, const float *tables,
                                  int n, int threads, float *global,
                                  float *back) {
  global_job j = {f, tables, n, global, back};
  satf_parallel_for(SATF_FIBER_GLOBAL_NPHI, threads, global_slice, &j, NULL,
                    NULL);
}
