/* fiber.c - the scattering function of one hair fibre: d'Eon et al. 2011
 * (paper 003) longitudinal M_p and attenuation A_p, Chiang et al. 2016's
 * logistic N_p and roughness mappings, with Cycles' parameter meanings (see
 * satf/fiber.h for the frame and the units). */
#include "satf/fiber.h"

#include <math.h>

#include "satf/math.h"

static float clampf(float x, float lo, float hi) {
  return x < lo ? lo : x > hi ? hi : x;
}

static float safe_sqrtf(float x) { return sqrtf(x > 0.0f ? x : 0.0f); }

static float safe_asinf(float x) { return asinf(clampf(x, -1.0f, 1.0f)); }

void satf_fiber_sigma_a_melanin(float melanin, float redness,
                                float sigma_a[3]) {
  /* Cycles' melanin mode: the slider maps to a concentration through
   * -log(1 - m) so equal steps look like equal steps in darkness. */
  melanin = clampf(melanin, 0.0f, 1.0f);
  redness = clampf(redness, 0.0f, 1.0f);
  float q = -logf(fmaxf(1.0f - melanin, 1e-4f));
  float eu = q * (1.0f - redness), pheo = q * redness;
  static const float eu_rgb[3] = {0.506f, 0.841f, 1.653f};
  static const float pheo_rgb[3] = {0.343f, 0.733f, 1.924f};
  for (int c = 0; c < 3; c++)
    sigma_a[c] = eu * eu_rgb[c] + pheo * pheo_rgb[c];
}

void satf_fiber_sigma_a_concentration_pbrt(float eumelanin, float pheomelanin,
                                           float sigma_a[3]) {
  static const float eu_rgb[3] = {0.419f, 0.697f, 1.37f};
  static const float pheo_rgb[3] = {0.187f, 0.4f, 1.05f};
  for (int c = 0; c < 3; c++)
    sigma_a[c] = eumelanin * eu_rgb[c] + pheomelanin * pheo_rgb[c];
}

float satf_fiber_longitudinal_variance(float beta_m) {
  /* Chiang 2016 eq. 7 */
  float b = clampf(beta_m, 0.0f, 1.0f);
  float b2 = b * b, b4 = b2 * b2, b8 = b4 * b4, b16 = b8 * b8;
  float r = 0.726f * b + 0.812f * b2 + 3.7f * b16 * b4;
  return r * r;
}

float satf_fiber_azimuthal_scale(float beta_n) {
  /* Chiang 2016 eq. 8, sqrt(pi / 8) (0.265 b + 1.194 b^2 + 5.372 b^22) */
  float b = clampf(beta_n, 0.0f, 1.0f);
  float b2 = b * b, b4 = b2 * b2, b8 = b4 * b4, b16 = b8 * b8;
  return 0.626657069f * (0.265f * b + 1.194f * b2 + 5.372f * b16 * b4 * b2);
}

float satf_fiber_fresnel(float cos_theta_i, float eta) {
  cos_theta_i = clampf(cos_theta_i, -1.0f, 1.0f);
  if (cos_theta_i < 0.0f) { /* from inside: swap the media */
    eta = 1.0f / eta;
    cos_theta_i = -cos_theta_i;
  }
  float sin2_i = 1.0f - cos_theta_i * cos_theta_i;
  float sin2_t = sin2_i / (eta * eta);
  if (sin2_t >= 1.0f)
    return 1.0f; /* total internal reflection */
  float cos_t = safe_sqrtf(1.0f - sin2_t);
  float r_par = (eta * cos_theta_i - cos_t) / (eta * cos_theta_i + cos_t);
  float r_perp = (cos_theta_i - eta * cos_t) / (cos_theta_i + eta * cos_t);
  return 0.5f * (r_par * r_par + r_perp * r_perp);
}

/* The modified Bessel function I0 by its power series (converges for the
 * arguments M_p uses with v > 0.1, x < 10). */
static float bessel_i0(float x) {
  float x2 = x * x, term = 1.0f, sum = 1.0f;
  for (int k = 1; k < 24; k++) {
    term *= x2 / (4.0f * (float)k * (float)k);
    sum += term;
    if (term < sum * 1e-8f)
      break;
  }
  return sum;
}

static float log_bessel_i0(float x) {
  /* the asymptotic expansion I0(x) ~ e^x / sqrt(2 pi x) (1 + 1 / (8 x) +
   * 9 / (128 x^2) + 225 / (3072 x^3)), within 1e-5 for x > 12 (pbrt's and
   * Cycles' one term leaves 5e-4) */
  if (x > 12.0f) {
    float r = 1.0f / x;
    return x - 0.5f * logf(SATF_TWO_PI_F * x) +
           log1pf(r * (0.125f + r * (0.0703125f + r * 0.0732421875f)));
  }
  return logf(bessel_i0(x));
}

float satf_fiber_mp(float cos_ti, float cos_to, float sin_ti, float sin_to,
                    float v) {
  /* d'Eon 2011 eq. 7 */
  float a = cos_ti * cos_to / v, b = sin_ti * sin_to / v;
  if (v <= 0.1f)
    /* csch(1/v) / (2 v) = e^(-1/v) / v (1 - e^(-2/v))^-1 ~ e^(-1/v) / v:
     * everything in the exponent (d'Eon's appendix) */
    return expf(log_bessel_i0(a) - b - 1.0f / v - logf(v));
  return expf(-b) * bessel_i0(a) / (2.0f * v * sinhf(1.0f / v));
}

float satf_fiber_phi(int p, float gamma_o, float gamma_t) {
  return 2.0f * (float)p * gamma_t - 2.0f * gamma_o + (float)p * SATF_PI_F;
}

static float logistic(float x, float s) {
  float e = expf(-fabsf(x) / s);
  return e / (s * (1.0f + e) * (1.0f + e));
}

static float logistic_cdf(float x, float s) {
  float arg = -x / s;
  if (arg > 80.0f)
    return 0.0f;
  return 1.0f / (1.0f + expf(arg));
}

float satf_fiber_trimmed_logistic(float x, float s) {
  /* Chiang 2016 eq. 11: renormalised to [-pi, pi] */
  float mass = 1.0f - 2.0f * logistic_cdf(-SATF_PI_F, s);
  return logistic(x, s) / mass;
}

float satf_fiber_sample_trimmed_logistic(float u, float s) {
  float lo = logistic_cdf(-SATF_PI_F, s), k = 1.0f - 2.0f * lo;
  float x = -s * logf(1.0f / (u * k + lo) - 1.0f);
  return clampf(x, -SATF_PI_F, SATF_PI_F);
}

float satf_fiber_np(float phi, int p, float s, float gamma_o, float gamma_t) {
  /* Chiang 2016 eq. 10: the deviation from the lobe's exit azimuth,
   * wrapped to [-pi, pi] */
  float d = phi - satf_fiber_phi(p, gamma_o, gamma_t);
  d = fmodf(d + SATF_PI_F, SATF_TWO_PI_F);
  if (d < 0.0f)
    d += SATF_TWO_PI_F;
  d -= SATF_PI_F;
  return satf_fiber_trimmed_logistic(d, s);
}

void satf_fiber_ap(float cos_theta_o, float eta, float h, float T,
                   float ap[SATF_FIBER_LOBES]) {
  /* d'Eon 2011 eq. 12-14: the Fresnel factor is the same at every
   * interface of the circular cross-section, at the 3-D incidence angle
   * cos(theta_o) cos(gamma_o) */
  float cos_gamma_o = safe_sqrtf(1.0f - h * h);
  float f = satf_fiber_fresnel(cos_theta_o * cos_gamma_o, eta);
  ap[0] = f;
  ap[1] = (1.0f - f) * (1.0f - f) * T;
  ap[2] = ap[1] * T * f;
  float tf = T * f;
  ap[3] = tf < 1.0f ? ap[2] * tf / (1.0f - tf) : 0.0f;
}

float satf_fiber_eta_prime(float eta, float sin_theta_o) {
  float cos_theta_o = safe_sqrtf(1.0f - sin_theta_o * sin_theta_o);
  if (cos_theta_o < 1e-6f)
    cos_theta_o = 1e-6f;
  return safe_sqrtf(eta * eta - sin_theta_o * sin_theta_o) / cos_theta_o;
}

float satf_fiber_transmittance(float sigma_a, float h, float eta,
                               float sin_theta_o) {
  float sin_theta_t = sin_theta_o / eta;
  float cos_theta_t = safe_sqrtf(1.0f - sin_theta_t * sin_theta_t);
  float sin_gamma_t = h / satf_fiber_eta_prime(eta, sin_theta_o);
  float cos_gamma_t = safe_sqrtf(1.0f - sin_gamma_t * sin_gamma_t);
  return expf(-sigma_a * 2.0f * cos_gamma_t / cos_theta_t);
}

satf_fiber_material satf_fiber_material_default(void) {
  satf_fiber_material m;
  m.melanin = 0.6f;
  m.redness = 0.0f;
  m.roughness = 0.3f;
  m.radial_roughness = 0.3f;
  m.cuticle_tilt = 2.0f * SATF_PI_F / 180.0f;
  m.ior = 1.55f;
  return m;
}

void satf_fiber_init_sigma_a(satf_fiber *f, const float sigma_a[3],
                             float beta_m, float beta_n, float alpha,
                             float eta) {
  f->eta = eta;
  float v = satf_fiber_longitudinal_variance(beta_m);
  /* Cycles clamps v and s below so M_p and N_p stay finite */
  v = fmaxf(v, 1e-4f);
  f->v[0] = v;
  f->v[1] = 0.25f * v;
  f->v[2] = 4.0f * v;
  f->v[3] = 4.0f * v;
  f->s = fmaxf(satf_fiber_azimuthal_scale(beta_n), 1e-3f);
  for (int c = 0; c < 3; c++)
    f->sigma_a[c] = fmaxf(sigma_a[c], 0.0f);
  f->alpha = alpha;
  f->sin_2k_alpha[0] = sinf(alpha);
  f->cos_2k_alpha[0] =
      safe_sqrtf(1.0f - f->sin_2k_alpha[0] * f->sin_2k_alpha[0]);
  for (int k = 1; k < 3; k++) {
    float sp = f->sin_2k_alpha[k - 1], cp = f->cos_2k_alpha[k - 1];
    f->sin_2k_alpha[k] = 2.0f * cp * sp;
    f->cos_2k_alpha[k] = cp * cp - sp * sp;
  }
}

void satf_fiber_init(satf_fiber *f, const satf_fiber_material *m) {
  float sigma_a[3];
  satf_fiber_sigma_a_melanin(m->melanin, m->redness, sigma_a);
  satf_fiber_init_sigma_a(f, sigma_a, m->roughness, m->radial_roughness,
                          m->cuticle_tilt, m->ior);
}

void satf_fiber_tilt(const satf_fiber *f, int p, float sin_theta_o,
                     float cos_theta_o, float *sin_p, float *cos_p) {
  float s = sin_theta_o, c = cos_theta_o;
  switch (p) {
  case 0: /* + 2 alpha */
    *sin_p = s * f->cos_2k_alpha[1] + c * f->sin_2k_alpha[1];
    *cos_p = c * f->cos_2k_alpha[1] - s * f->sin_2k_alpha[1];
    break;
  case 1: /* - alpha */
    *sin_p = s * f->cos_2k_alpha[0] - c * f->sin_2k_alpha[0];
    *cos_p = c * f->cos_2k_alpha[0] + s * f->sin_2k_alpha[0];
    break;
  case 2: /* - 4 alpha */
    *sin_p = s * f->cos_2k_alpha[2] - c * f->sin_2k_alpha[2];
    *cos_p = c * f->cos_2k_alpha[2] + s * f->sin_2k_alpha[2];
    break;
  default:
    *sin_p = s;
    *cos_p = c;
    break;
  }
  *cos_p = fabsf(*cos_p);
}

void satf_fiber_eval_lobes(const satf_fiber *f, const float wo[3],
                           const float wi[3], float h,
                           float out[SATF_FIBER_LOBES][3]) {
  h = clampf(h, -1.0f, 1.0f);
  float sin_theta_o = clampf(wo[0], -1.0f, 1.0f);
  float cos_theta_o = safe_sqrtf(1.0f - sin_theta_o * sin_theta_o);
  float phi_o = atan2f(wo[2], wo[1]);
  float sin_theta_i = clampf(wi[0], -1.0f, 1.0f);
  float cos_theta_i = safe_sqrtf(1.0f - sin_theta_i * sin_theta_i);
  float phi_i = atan2f(wi[2], wi[1]);
  float gamma_o = safe_asinf(h);
  float sin_gamma_t = h / satf_fiber_eta_prime(f->eta, sin_theta_o);
  float gamma_t = safe_asinf(sin_gamma_t);
  float phi = phi_i - phi_o;

  float ap[3][SATF_FIBER_LOBES];
  for (int c = 0; c < 3; c++) {
    float T = satf_fiber_transmittance(f->sigma_a[c], h, f->eta, sin_theta_o);
    satf_fiber_ap(cos_theta_o, f->eta, h, T, ap[c]);
  }
  for (int p = 0; p < SATF_FIBER_LOBES; p++) {
    float sp, cp;
    satf_fiber_tilt(f, p, sin_theta_o, cos_theta_o, &sp, &cp);
    float mp = satf_fiber_mp(cos_theta_i, cp, sin_theta_i, sp, f->v[p]);
    float np = p < 3 ? satf_fiber_np(phi, p, f->s, gamma_o, gamma_t)
                     : 1.0f / SATF_TWO_PI_F;
    for (int c = 0; c < 3; c++)
      out[p][c] = mp * np * ap[c][p];
  }
}

void satf_fiber_eval(const satf_fiber *f, const float wo[3], const float wi[3],
                     float h, float out[3]) {
  float lobes[SATF_FIBER_LOBES][3];
  satf_fiber_eval_lobes(f, wo, wi, h, lobes);
  for (int c = 0; c < 3; c++) {
    out[c] = 0.0f;
    for (int p = 0; p < SATF_FIBER_LOBES; p++)
      out[c] += lobes[p][c];
  }
}

/* The trimmed logistic's CDF on [-pi, pi]. */
static float trimmed_logistic_cdf(float x, float s) {
  float lo = logistic_cdf(-SATF_PI_F, s);
  return (logistic_cdf(x, s) - lo) / (1.0f - 2.0f * lo);
}

float satf_fiber_np_integral(float phi0, float phi1, int p, float s,
                             float gamma_o, float gamma_t) {
  float len = phi1 - phi0;
  if (len <= 0.0f)
    return 0.0f;
  if (len >= SATF_TWO_PI_F)
    return 1.0f;
  /* the arc's start relative to the lobe's centre, wrapped to [-pi, pi) */
  float a = phi0 - satf_fiber_phi(p, gamma_o, gamma_t);
  a = fmodf(a + SATF_PI_F, SATF_TWO_PI_F);
  if (a < 0.0f)
    a += SATF_TWO_PI_F;
  a -= SATF_PI_F;
  float b = a + len;
  if (b <= SATF_PI_F)
    return trimmed_logistic_cdf(b, s) - trimmed_logistic_cdf(a, s);
  return 1.0f - trimmed_logistic_cdf(a, s) +
         trimmed_logistic_cdf(b - SATF_TWO_PI_F, s);
}
