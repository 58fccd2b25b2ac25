/* fiber_tables.c - tables of the fibre's lobes for shaders that evaluate
 * them at every point of many strands: the azimuthal scattering averaged
 * across each half of the fibre (satf_fiber_azimuthal_table) and the
 * four lobes' longitudinal scattering (satf_fiber_mp_table). */
#include <math.h>
#include <stddef.h>

#include "satf/common.h"
#include "satf/fiber.h"
#include "satf/math.h"

typedef struct az_job {
  const satf_fiber *f;
  float *out;
} az_job;

/* Row k: every half, lobe and column at |sin theta_o| = k / (rows - 1). */
static int az_row(void *ctx, size_t k, int thread) {
  (void)thread;
  const az_job *j = ctx;
  const satf_fiber *f = j->f;
  float sin_o = (float)k / (float)(SATF_FIBER_AZ_ROWS - 1);
  float cos_o = sqrtf(fmaxf(1.0f - sin_o * sin_o, 0.0f));
  float eta_p = satf_fiber_eta_prime(f->eta, sin_o);
  for (int half = 0; half < 2; half++) {
    float acc[SATF_FIBER_LOBES][SATF_FIBER_AZ_COLS][3] = {{{0.0f}}};
    for (int i = 0; i < SATF_FIBER_AZ_H; i++) {
      /* midpoints in gamma_o = asin h over [-pi / 2, 0] or [0, pi / 2],
       * weighted by dh = cos gamma_o dgamma_o: the lobes' exit azimuths
       * Phi_p are smooth in gamma_o, where near the edge h = +-1 they
       * sweep a quarter of the circle in the last 1% of h (R: Phi = -2
       * gamma_o), which midpoints in h miss */
      float g = ((float)i + 0.5f) / (float)SATF_FIBER_AZ_H * 0.5f * SATF_PI_F;
      float gamma_o = half ? g : -g;
      float h = sinf(gamma_o);
      float w = cosf(g) * 0.5f * SATF_PI_F / (float)SATF_FIBER_AZ_H;
      float gamma_t = asinf(fminf(fmaxf(h / eta_p, -1.0f), 1.0f));
      float ap[3][SATF_FIBER_LOBES];
      for (int c = 0; c < 3; c++)
        satf_fiber_ap(cos_o, f->eta, h,
                      satf_fiber_transmittance(f->sigma_a[c], h, f->eta, sin_o),
                      ap[c]);
      for (int col = 0; col < SATF_FIBER_AZ_COLS; col++) {
        float phi =
            -SATF_PI_F + SATF_TWO_PI_F * (float)col / (float)SATF_FIBER_AZ_COLS;
        for (int p = 0; p < SATF_FIBER_LOBES; p++) {
          float np = p < 3 ? satf_fiber_np(phi, p, f->s, gamma_o, gamma_t)
                           : 1.0f / SATF_TWO_PI_F;
          for (int c = 0; c < 3; c++)
            acc[p][col][c] += w * np * ap[c][p];
        }
      }
    }
    for (int p = 0; p < SATF_FIBER_LOBES; p++) {
      size_t layer = (size_t)half * SATF_FIBER_LOBES + (size_t)p;
      float *o =
          j->out + ((layer * SATF_FIBER_AZ_ROWS + k) * SATF_FIBER_AZ_COLS) * 3;
      for (int col = 0; col < SATF_FIBER_AZ_COLS; col++)
        for (int c = 0; c < 3; c++)
          o[3 * col + c] = acc[p][col][c];
    }
  }
  return 0;
}

void satf_fiber_azimuthal_table(const satf_fiber *f, int threads, float *out) {
  az_job j = {f, out};
  satf_parallel_for(SATF_FIBER_AZ_ROWS, threads, az_row, &j, NULL, NULL);
}

void satf_fiber_azimuthal_lookup(const float *table, int layer,
                                 float sin_theta_o, float phi, float out[3]) {
  /* rows clamped, columns periodic, as the texture's CLAMP_TO_EDGE and
   * REPEAT read them */
  float y = fminf(fabsf(sin_theta_o), 1.0f) * (float)(SATF_FIBER_AZ_ROWS - 1);
  float x = (phi + SATF_PI_F) / SATF_TWO_PI_F * (float)SATF_FIBER_AZ_COLS;
  x -= (float)SATF_FIBER_AZ_COLS * floorf(x / (float)SATF_FIBER_AZ_COLS);
  int y0 = (int)y, x0 = (int)x;
  y0 = y0 > SATF_FIBER_AZ_ROWS - 2 ? SATF_FIBER_AZ_ROWS - 2 : y0;
  x0 = x0 > SATF_FIBER_AZ_COLS - 1 ? SATF_FIBER_AZ_COLS - 1 : x0;
  float fy = y - (float)y0, fx = x - (float)x0;
  int x1 = (x0 + 1) % SATF_FIBER_AZ_COLS;
  const float *base =
      table + (size_t)layer * SATF_FIBER_AZ_ROWS * SATF_FIBER_AZ_COLS * 3;
  for (int c = 0; c < 3; c++) {
    float v[2];
    for (int r = 0; r < 2; r++) {
      const float *row = base + (size_t)(y0 + r) * SATF_FIBER_AZ_COLS * 3;
      v[r] = row[3 * x0 + c] * (1.0f - fx) + row[3 * x1 + c] * fx;
    }
    out[c] = v[0] * (1.0f - fy) + v[1] * fy;
  }
}

void satf_fiber_mp_table(const satf_fiber *f, float v_rest, int n, float *out) {
  for (int b = 0; b < n; b++)
    for (int a = 0; a < n; a++) {
      float si = -1.0f + 2.0f * (float)a / (float)(n - 1);
      float so = -1.0f + 2.0f * (float)b / (float)(n - 1);
      float ci = sqrtf(fmaxf(1.0f - si * si, 0.0f));
      float co = sqrtf(fmaxf(1.0f - so * so, 0.0f));
      float *o = out + 4 * ((size_t)b * (size_t)n + (size_t)a);
      for (int p = 0; p < 3; p++) {
        float sp, cp;
        satf_fiber_tilt(f, p, so, co, &sp, &cp);
        o[p] = satf_fiber_mp(ci, cp, si, sp, f->v[p]); /* d'Eon 2011 eq. 7 */
      }
      o[3] = satf_fiber_mp(ci, co, si, so, v_rest);
    }
}
