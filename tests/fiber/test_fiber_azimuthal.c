/* test_fiber_azimuthal.c - the lobes' azimuthal scattering averaged over
 * each half of the fibre (satf_fiber_azimuthal_table): each lobe's N_p
 * integrates over phi to its mean A_p over the half (D_p is normalised),
 * the two halves mirror each other (Phi_p is odd in h, A_p even), and the
 * table's bilinear look-up follows a direct average over 4,096 offsets
 * at angles between its rows and columns. */
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

#define FINE 4096 /* midpoints of a half for the direct averages */

static float *table_of(satf_fiber *f, float melanin, float beta_n) {
  satf_fiber_material m = satf_fiber_material_default();
  m.melanin = melanin;
  m.radial_roughness = beta_n;
  satf_fiber_init(f, &m);
  float *t = malloc((size_t)SATF_FIBER_AZ_LAYERS * SATF_FIBER_AZ_ROWS *
                    SATF_FIBER_AZ_COLS * 3 * sizeof(float));
  assert_non_null(t);
  satf_fiber_azimuthal_table(f, 2, t);
  return t;
}

/* Offset i of FINE midpoints of half `half` ([-1, 0] or [0, 1]). */
static float fine_h(int i, int half) {
  return ((float)i + 0.5f) / (float)FINE - (half ? 0.0f : 1.0f);
}

/* The direct average over the half of N_p A_p (channel c) at sin theta_o
 * and phi, and of A_p alone (into *ap_mean). */
static double direct(const satf_fiber *f, int half, int p, int c, float sin_o,
                     float phi, double *ap_mean) {
  float cos_o = sqrtf(1.0f - sin_o * sin_o);
  double sum = 0.0, asum = 0.0;
  for (int i = 0; i < FINE; i++) {
    float h = fine_h(i, half), ap[SATF_FIBER_LOBES];
    float T = satf_fiber_transmittance(f->sigma_a[c], h, f->eta, sin_o);
    satf_fiber_ap(cos_o, f->eta, h, T, ap);
    float gt = asinf(h / satf_fiber_eta_prime(f->eta, sin_o));
    float np = p < 3 ? satf_fiber_np(phi, p, f->s, asinf(h), gt)
                     : 1.0f / SATF_TWO_PI_F;
    sum += np * ap[p];
    asum += ap[p];
  }
  if (ap_mean)
    *ap_mean = asum / FINE;
  return sum / FINE;
}

static const float *row_of(const float *t, int layer, int k) {
  return t + (((size_t)layer * SATF_FIBER_AZ_ROWS + (size_t)k) *
              SATF_FIBER_AZ_COLS) *
                 3;
}

static void lobes_integrate_to_attenuation(void **state) {
  (void)state;
  satf_fiber f;
  float *t = table_of(&f, 0.6f, 0.3f);
  double worst = 0.0;
  for (int k = 0; k < SATF_FIBER_AZ_ROWS; k += 9)
    for (int layer = 0; layer < SATF_FIBER_AZ_LAYERS; layer++) {
      int half = layer / SATF_FIBER_LOBES, p = layer % SATF_FIBER_LOBES;
      float sin_o = (float)k / (SATF_FIBER_AZ_ROWS - 1);
      if (sin_o > 0.99f)
        continue; /* grazing: no path through the fibre */
      const float *row = row_of(t, layer, k);
      for (int c = 0; c < 3; c++) {
        double integral = 0.0, ap;
        for (int j = 0; j < SATF_FIBER_AZ_COLS; j++)
          integral += row[3 * j + c] * SATF_TWO_PI / SATF_FIBER_AZ_COLS;
        direct(&f, half, p, c, sin_o, 0.0f, &ap);
        double err = fabs(integral - ap) / fmax(ap, 1e-3);
        worst = err > worst ? err : worst;
        if (err > 0.005)
          fail_msg("layer %d row %d channel %d: int N_p %.5f, mean A_p %.5f",
                   layer, k, c, integral, ap);
      }
    }
  printf("integral over phi against the mean A_p: worst %.4f\n", worst);
  free(t);
}

static void halves_mirror(void **state) {
  (void)state;
  satf_fiber f;
  float *t = table_of(&f, 0.3f, 0.3f);
  for (int k = 0; k < SATF_FIBER_AZ_ROWS; k += 7)
    for (int p = 0; p < SATF_FIBER_LOBES; p++) {
      const float *a = row_of(t, p, k), *b = row_of(t, SATF_FIBER_LOBES + p, k);
      for (int j = 1; j < SATF_FIBER_AZ_COLS; j++) {
        int m = SATF_FIBER_AZ_COLS - j; /* phi_j = -phi_m */
        for (int c = 0; c < 3; c++)
          assert_near(a[3 * j + c], b[3 * m + c],
                      1e-4 * (fabs(a[3 * j + c]) + 1e-3));
      }
    }
  free(t);
}

/* Look-ups between rows and columns against the direct average, for
 * smooth, medium and rough hair, within 1.5% of the lobe's peak. */
static void lookup_follows_direct(void **state) {
  (void)state;
  const float beta_n[3] = {0.15f, 0.3f, 0.6f};
  for (int r = 0; r < 3; r++) {
    satf_fiber f;
    float *t = table_of(&f, 0.6f, beta_n[r]);
    unsigned seed = 7;
    double worst = 0.0;
    for (int n = 0; n < 300; n++) {
      seed = seed * 1103515245u + 12345u;
      float sin_o = 0.95f * (float)((seed >> 8) & 0xffff) / 65535.0f;
      seed = seed * 1103515245u + 12345u;
      float phi = SATF_TWO_PI_F * ((float)((seed >> 8) & 0xffff) / 65535.0f) -
                  SATF_PI_F;
      int layer = n % SATF_FIBER_AZ_LAYERS;
      int half = layer / SATF_FIBER_LOBES, p = layer % SATF_FIBER_LOBES;
      float got[3];
      satf_fiber_azimuthal_lookup(t, layer, (n & 1) ? sin_o : -sin_o, phi, got);
      /* the lobe's peak over phi at this inclination */
      int k = (int)lroundf(sin_o * (SATF_FIBER_AZ_ROWS - 1));
      const float *row = row_of(t, layer, k);
      double peak = 0.0;
      for (int j = 0; j < SATF_FIBER_AZ_COLS; j++)
        peak = row[3 * j + 1] > peak ? row[3 * j + 1] : peak;
      double want = direct(&f, half, p, 1, sin_o, phi, NULL);
      double err = fabs(got[1] - want) / fmax(peak, 1e-6);
      worst = err > worst ? err : worst;
      if (err > 0.015)
        fail_msg("beta_n %.2f layer %d sin_o %.3f phi %.3f: table %.5f, "
                 "direct %.5f, peak %.5f",
                 beta_n[r], layer, sin_o, phi, got[1], want, peak);
    }
    printf("beta_n %.2f: look-up against the direct average, worst %.4f of "
           "the peak\n",
           beta_n[r], worst);
    free(t);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(lobes_integrate_to_attenuation),
      cmocka_unit_test(halves_mirror),
      cmocka_unit_test(lookup_follows_direct),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
