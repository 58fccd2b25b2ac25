/* test_fiber_dual.c - the dual-scattering tables (Zinke et al. 2008) from
 * the fibre model: energy (a_f + a_b = 1 without absorption, less with),
 * the fractions against a quadrature of the lobes, the local
 * back-scattering against a simulated Poisson walk, and f_back integrating
 * to A_b. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "satf/fiber.h"
#include "satf/math.h"
#include "test_util.h"

#define NB 16

static float field(const float *t, int k, int fld, int c) {
  return t[((size_t)k * SATF_FIBER_DUAL_FIELDS + fld) * 3 + c];
}

/* The default material with the given melanin, and its tables. */
static void brown_tables(float melanin, satf_fiber *f, float *t) {
  satf_fiber_material m = satf_fiber_material_default();
  m.melanin = melanin;
  satf_fiber_init(f, &m);
  satf_fiber_dual_tables(f, NB, t);
}

static void np_integral_matches_quadrature(void **state) {
  (void)state;
  const float scales[] = {0.05f, 0.25f, 1.0f};
  for (int k = 0; k < 3; k++)
    for (int p = 0; p < 3; p++)
      for (double a = -7; a < 7; a += 1.3)
        for (double len = 0.4; len < 6.3; len += 1.9) {
          float s = scales[k], go = 0.4f, gt = 0.25f;
          double q = 0;
          const int n = 4000;
          for (int i = 0; i < n; i++)
            q += satf_fiber_np((float)(a + len * (i + 0.5) / n), p, s, go, gt);
          q *= len / n;
          assert_near(
              satf_fiber_np_integral((float)a, (float)(a + len), p, s, go, gt),
              q, 2e-4);
        }
}

static void lossless_fractions_sum_to_one(void **state) {
  (void)state;
  const float zero[3] = {0, 0, 0};
  const float beta_ns[] = {0.1f, 0.3f, 0.8f};
  for (int b = 0; b < 3; b++) {
    satf_fiber f;
    satf_fiber_init_sigma_a(&f, zero, 0.3f, beta_ns[b], 0.035f, 1.55f);
    float *t = malloc(sizeof(float) * NB * SATF_FIBER_DUAL_FIELDS * 3);
    assert_non_null(t);
    satf_fiber_dual_tables(&f, NB, t);
    for (int k = 0; k < NB; k++)
      for (int c = 0; c < 3; c++) {
        float af = field(t, k, SATF_FIBER_DUAL_AF, c);
        float ab = field(t, k, SATF_FIBER_DUAL_AB, c);
        assert_near(af + ab, 1.0, 1e-3);
        /* without absorption, TT carries most light on along the path (up
         * to 45 degrees; at grazing light R's Fresnel takes over), less so
         * the rougher the azimuth (eq. 6's arriving half-circle) */
        assert_true(ab > 0.02f && (k >= NB / 2 || af > (b < 2 ? 2 : 1) * ab));
        assert_true(field(t, k, SATF_FIBER_DUAL_A_B, c) >= 0);
        assert_true(field(t, k, SATF_FIBER_DUAL_SIGMA_B2, c) > 0);
        assert_true(isfinite(field(t, k, SATF_FIBER_DUAL_DELTA_B, c)));
      }
    free(t);
  }
}

/* With melanin: a_f + a_b < 1, the darker channel (blue) loses more, and
 * a_f against a brute-force quadrature of sum_p A_p N_p over the forward
 * half-circle, the arriving azimuths and h (eq. 6). */
static void absorbing_fractions(void **state) {
  (void)state;
  satf_fiber f;
  float t[NB * SATF_FIBER_DUAL_FIELDS * 3];
  brown_tables(0.3f, &f, t);
  for (int k = 0; k < NB; k++) {
    for (int c = 0; c < 3; c++) {
      float af = field(t, k, SATF_FIBER_DUAL_AF, c);
      float ab = field(t, k, SATF_FIBER_DUAL_AB, c);
      assert_true(af + ab < 1.0f && af > 0 && ab > 0);
    }
    assert_true(field(t, k, SATF_FIBER_DUAL_AF, 2) <
                field(t, k, SATF_FIBER_DUAL_AF, 0));
  }
  const int ks[] = {0, 7, 15};
  for (int i = 0; i < 3; i++) {
    int k = ks[i];
    double theta = (k + 0.5) / NB * SATF_PI / 2;
    float sin_t = (float)sin(theta), cos_t = (float)cos(theta);
    float etap = satf_fiber_eta_prime(f.eta, sin_t);
    for (int c = 0; c < 3; c++) {
      /* eq. 6: the light arriving over the half-circle of azimuths psi in
       * (-pi / 2, pi / 2) around the path, the exit in the path's fixed
       * forward half: exit azimuth (relative to the arriving ray's, 0 back
       * towards the light) more than pi / 2 from psi */
      double fwd = 0;
      const int nh = 250, npsi = 40, nphi = 400;
      for (int j = 0; j < nh; j++) {
        float h = (float)(-1 + 2 * (j + 0.5) / nh);
        float ap[SATF_FIBER_LOBES];
        satf_fiber_ap(cos_t, f.eta, h,
                      satf_fiber_transmittance(f.sigma_a[c], h, f.eta, sin_t),
                      ap);
        for (int u = 0; u < npsi; u++) {
          double psi = SATF_PI * ((u + 0.5) / npsi - 0.5);
          for (int q = 0; q < nphi; q++) {
            double phi = psi + SATF_PI / 2 + SATF_PI * (q + 0.5) / nphi;
            for (int p = 0; p < 3; p++)
              fwd += ap[p] * satf_fiber_np((float)phi, p, f.s, asinf(h),
                                           asinf(h / etap));
            fwd += ap[3] / (2 * SATF_PI);
          }
        }
      }
      fwd *= SATF_PI / nphi / nh / npsi;
      assert_near(field(t, k, SATF_FIBER_DUAL_AF, c), fwd, 2e-3 * fwd + 1e-5);
    }
  }
}

static double uniform(uint64_t *x) {
  *x ^= *x << 13;
  *x ^= *x >> 7;
  *x ^= *x << 17;
  return ((double)(*x >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

/* A_b, Delta_b and sigma_b^2 (the local back-scattering of eq. 11-17 with
 * hair crossings as a Poisson process) against a simulation of that
 * process: light enters at depth 0, crosses hairs at unit rate per expected
 * crossing, each crossing sends a_f on, a_b back and absorbs the rest; what
 * comes back out after one or three backward events is scattered once more
 * by the point's own fibre (a_f). The path's shift and variance: one
 * alpha_b, beta_b^2 per backward event, one alpha_f, beta_f^2 per forward
 * one (the point's own included). */
static void back_scattering_matches_poisson_walk(void **state) {
  (void)state;
  satf_fiber f;
  float t[NB * SATF_FIBER_DUAL_FIELDS * 3];
  brown_tables(0.15f, &f, t);
  uint64_t rng = 0x2545F4914F6CDD1Dull;
  const int ks[] = {0, 9};
  for (int i = 0; i < 2; i++)
    for (int c = 0; c < 3; c += 2) {
      int k = ks[i];
      double af = field(t, k, SATF_FIBER_DUAL_AF, c);
      double ab = field(t, k, SATF_FIBER_DUAL_AB, c);
      double alf = field(t, k, SATF_FIBER_DUAL_ALPHA_F, c);
      double alb = field(t, k, SATF_FIBER_DUAL_ALPHA_B, c);
      double bf = field(t, k, SATF_FIBER_DUAL_BETA_F2, c);
      double bb = field(t, k, SATF_FIBER_DUAL_BETA_B2, c);
      double sw[4] = {0}, sd = 0, sdd = 0, sv = 0;
      const int n = 400000;
      for (int w = 0; w < n; w++) {
        double m = 0, dir = 1, wt = 1;
        int backs = 0, fwds = 0;
        for (;;) {
          m += dir * -log(uniform(&rng));
          if (m < 0) {
            double a = wt * af; /* the point's own fibre */
            double d = backs * alb + (fwds + 1) * alf;
            sw[backs] += a;
            sd += a * d;
            sdd += a * d * d;
            sv += a * (backs * bb + (fwds + 1) * bf);
            break;
          }
          /* forward or backward in proportion, the weight keeps the rest */
          wt *= af + ab;
          if (uniform(&rng) * (af + ab) < af) {
            fwds++;
          } else {
            backs++;
            dir = -dir;
          }
          if (backs > 3 || wt < 1e-9)
            break;
        }
      }
      double a1 = sw[1] / n, a3 = sw[3] / n, ab_sim = a1 + a3;
      double mean = sd / (sw[1] + sw[3]);
      double var = (sv + sdd) / (sw[1] + sw[3]) - mean * mean;
      /* the sampling error: ~1% of A_b, the shift and variance ~1% */
      assert_near(field(t, k, SATF_FIBER_DUAL_A_B, c), ab_sim, 0.02 * ab_sim);
      assert_near(field(t, k, SATF_FIBER_DUAL_DELTA_B, c), mean,
                  0.02 * fabs(mean) + 2e-3);
      assert_near(field(t, k, SATF_FIBER_DUAL_SIGMA_B2, c), var, 0.03 * var);
      /* Zinke's own sums (every crossing scatters: a_f^2i) give less where
       * hair absorbs; the walk's light also passes between hairs */
      double af2 = af * af;
      assert_true(ab * af2 / (1 - af2) < 0.9 * a1);
    }
}

/* f_back integrates over the sphere of incident directions to A_b. */
static void back_integrates_to_ab(void **state) {
  (void)state;
  satf_fiber f;
  float t[NB * SATF_FIBER_DUAL_FIELDS * 3];
  brown_tables(0.2f, &f, t);
  const double thetas[] = {0.0, 0.5, -0.9};
  for (int i = 0; i < 3; i++) {
    double to = thetas[i];
    float wo[3] = {(float)sin(to), (float)(cos(to) * cos(0.3)),
                   (float)(cos(to) * sin(0.3))};
    const int nt = 800, np = 400;
    double sum = 0;
    for (int a = 0; a < nt; a++) {
      double ti = -SATF_PI / 2 + SATF_PI * (a + 0.5) / nt;
      for (int b = 0; b < np; b++) {
        double pi = -SATF_PI + 2 * SATF_PI * (b + 0.5) / np;
        float wi[3] = {(float)sin(ti), (float)(cos(ti) * cos(pi)),
                       (float)(cos(ti) * sin(pi))};
        sum += satf_fiber_dual_back(t, NB, 1, wo, wi, 0.0f) * cos(ti);
      }
    }
    sum *= (SATF_PI / nt) * (2 * SATF_PI / np);
    float ab = satf_fiber_dual_lookup(t, NB, SATF_FIBER_DUAL_A_B, 1, (float)to);
    assert_true(ab > 1e-3f);
    /* 5%: A_b, Delta_b and sigma_b follow theta_d across the lobe
     * (measured 3.7% at most) */
    assert_near(sum, ab, 0.05 * ab);
  }
}

/* Trilinear interpolation of a table of satf_fiber_dual_global_table at
 * (theta_o, theta_i, phi), as GL filters a 3-D texture of it: texel
 * centres at the bins' centres, clamped at the edges. */
static float table_at(const float *tab, const satf_fiber *f, float to, float ti,
                      float phi, int c) {
  const int size[3] = {SATF_FIBER_GLOBAL_NH, SATF_FIBER_GLOBAL_ND,
                       SATF_FIBER_GLOBAL_NPHI};
  float u[3];
  satf_fiber_global_coords(f, to, ti, phi, u);
  int k0[3], k1[3];
  float w[3];
  for (int a = 0; a < 3; a++) {
    float v = fminf(fmaxf(u[a] * size[a] - 0.5f, 0.0f), (float)(size[a] - 1));
    k0[a] = (int)v;
    k1[a] = k0[a] + 1 < size[a] ? k0[a] + 1 : k0[a];
    w[a] = v - (float)k0[a];
  }
  float sum = 0.0f;
  for (int corner = 0; corner < 8; corner++) {
    int k[3];
    float wt = 1.0f;
    for (int a = 0; a < 3; a++) {
      int hi = (corner >> a) & 1;
      k[a] = hi ? k1[a] : k0[a];
      wt *= hi ? w[a] : 1.0f - w[a];
    }
    sum +=
        wt *
        tab[(((size_t)k[2] * size[1] + (size_t)k[1]) * size[0] + (size_t)k[0]) *
                3 +
            (size_t)c];
  }
  return sum;
}

/* The per-vertex global term of the cluster path's physical mode, read
 * from its table (satf_fiber_dual_global_table): trilinear interpolation
 * within 2.5% of the term's peak over random directions up to 66 degrees
 * from the hair's normal plane, for dark, blond and smooth hair (measured
 * 0.9-2.2%; 1.5-4.4% up to 72 degrees, where the term grows steeply
 * towards grazing; on a uniform 32^3 grid of theta_o, theta_i, phi the
 * smooth hair's was 13.8% at 72 degrees). The back-scattering's step at
 * |phi| = pi / 2 (the end of the backward half-circle) is left out within
 * a bin of it, where the texture blends the two sides. */
static void global_table(void **state) {
  (void)state;
  const float melanin[] = {0.6f, 0.2f, 0.6f}, rough[] = {0.3f, 0.3f, 0.15f};
  const double graze = 66.0 * SATF_PI / 180.0;
  enum { NTAB = 32 };
  size_t cells = (size_t)SATF_FIBER_GLOBAL_NH * SATF_FIBER_GLOBAL_ND *
                 SATF_FIBER_GLOBAL_NPHI * 3;
  float *g = malloc(2 * cells * sizeof *g), *b = g + cells;
  assert_non_null(g);
  for (int m = 0; m < 3; m++) {
    satf_fiber_material mat = satf_fiber_material_default();
    mat.melanin = melanin[m];
    mat.roughness = rough[m];
    satf_fiber f;
    satf_fiber_init(&f, &mat);
    float t[NTAB * SATF_FIBER_DUAL_FIELDS * 3];
    satf_fiber_dual_tables(&f, NTAB, t);
    satf_fiber_dual_global_table(&f, t, NTAB, 2, g, b);
    uint64_t x = 0x9e3779b97f4a7c15ull + (uint64_t)m;
    double peak_g = 0, peak_b = 0, err_g = 0, err_b = 0;
    for (int i = 0; i < 4000; i++) {
      float to = (float)((uniform(&x) - 0.5) * 2.0 * graze);
      float ti = (float)((uniform(&x) - 0.5) * 2.0 * graze);
      float phi = (float)(uniform(&x) * SATF_PI);
      float wo[3] = {sinf(to), cosf(to), 0.0f};
      float wi[3] = {sinf(ti), cosf(ti) * cosf(phi), cosf(ti) * sinf(phi)};
      float dg[3], db[3];
      satf_fiber_dual_global(&f, t, NTAB, wo, wi, 0.0f, 1.0f, dg, db);
      /* within a bin of the step (the warped bins' width there) */
      double w = 2.0 * f.s;
      int near_step = fabs(phi - SATF_PI / 2) <
                      w * 2.0 * asinh(SATF_PI / 2 / w) / SATF_FIBER_GLOBAL_NPHI;
      for (int c = 0; c < 3; c++) {
        float tg = table_at(g, &f, to, ti, phi, c),
              tb = table_at(b, &f, to, ti, phi, c);
        peak_g = fmax(peak_g, dg[c]);
        peak_b = fmax(peak_b, db[c]);
        err_g = fmax(err_g, fabs(tg - dg[c]));
        if (!near_step)
          err_b = fmax(err_b, fabs(tb - db[c]));
      }
    }
    printf("melanin %.1f roughness %.2f: global %.4f of its peak %.4f, back "
           "%.4f of %.4f\n",
           (double)melanin[m], (double)rough[m], err_g / peak_g, peak_g,
           err_b / peak_b, peak_b);
    assert_true(peak_g > 1e-3 && peak_b > 1e-3);
    assert_true(err_g <= 0.025 * peak_g);
    assert_true(err_b <= 0.025 * peak_b);
  }
  free(g);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(np_integral_matches_quadrature),
      cmocka_unit_test(lossless_fractions_sum_to_one),
      cmocka_unit_test(absorbing_fractions),
      cmocka_unit_test(back_scattering_matches_poisson_walk),
      cmocka_unit_test(back_integrates_to_ab),
      cmocka_unit_test(global_table),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
