/* test_fiber.c - the hair fibre model (satf/fiber.h) tested as pbrt-v4 tests
 * its HairBxDF: white furnaces in 3-D and in the normal plane, M_p and N_p
 * normalised, reciprocity, no NaN or negative value over a dense sweep, the
 * lobes against an independent geometric-optics trace of a cylinder, golden
 * values worked in Python (test_fiber_golden.py), and the melanin mapping
 * against Cycles' numbers. */
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

static void unit_dir(double theta, double phi, float w[3]) {
  w[0] = (float)sin(theta);
  w[1] = (float)(cos(theta) * cos(phi));
  w[2] = (float)(cos(theta) * sin(phi));
}

/* Cycles' melanin mode by hand: q = -ln(1 - m), eumelanin (0.506, 0.841,
 * 1.653), pheomelanin (0.343, 0.733, 1.924). */
static void melanin_matches_cycles(void **state) {
  (void)state;
  float s[3];
  satf_fiber_sigma_a_melanin(0.6f, 0.0f, s); /* q = 0.9162907 */
  assert_near(s[0], 0.4636431, 1e-5);
  assert_near(s[1], 0.7706005, 1e-5);
  assert_near(s[2], 1.5146285, 1e-5);
  satf_fiber_sigma_a_melanin(0.5f, 0.25f, s); /* q = ln 2 */
  double q = log(2.0);
  assert_near(s[0], q * (0.75 * 0.506 + 0.25 * 0.343), 1e-5);
  assert_near(s[1], q * (0.75 * 0.841 + 0.25 * 0.733), 1e-5);
  assert_near(s[2], q * (0.75 * 1.653 + 0.25 * 1.924), 1e-5);
  satf_fiber_sigma_a_melanin(1.0f, 1.0f, s); /* clamped at 1e-4 */
  assert_near(s[2], -log(1e-4) * 1.924, 1e-3);
  satf_fiber_sigma_a_melanin(0.0f, 0.7f, s); /* blond white: nothing */
  assert_true(s[0] == 0.0f && s[1] == 0.0f && s[2] == 0.0f);
  /* pbrt-v4's SigmaAFromConcentration(1.3, 0) */
  satf_fiber_sigma_a_concentration_pbrt(1.3f, 0.0f, s);
  assert_near(s[0], 0.5447, 1e-4);
  assert_near(s[2], 1.781, 1e-4);
  /* Chiang 2016 eq. 7-8 at the defaults 0.3 */
  double v = pow(0.726 * 0.3 + 0.812 * 0.09 + 3.7 * pow(0.3, 20), 2.0);
  assert_near(satf_fiber_longitudinal_variance(0.3f), v, 1e-6);
  double sc = sqrt(SATF_PI / 8) * (0.265 * 0.3 + 1.194 * 0.09);
  assert_near(satf_fiber_azimuthal_scale(0.3f), sc, 1e-6);
  satf_fiber_material m = satf_fiber_material_default();
  assert_near(m.ior, 1.55, 1e-6);
  assert_near(m.cuticle_tilt, 2.0 * SATF_PI / 180.0, 1e-7);
  assert_near(m.roughness, 0.3, 1e-7);
  assert_near(m.radial_roughness, 0.3, 1e-7);
}

static void fresnel_limits(void **state) {
  (void)state;
  double r0 = (1.55 - 1) / (1.55 + 1);
  assert_near(satf_fiber_fresnel(1.0f, 1.55f), r0 * r0, 1e-6);
  assert_near(satf_fiber_fresnel(0.0f, 1.55f), 1.0, 1e-6);
  /* from inside beyond the critical angle: total internal reflection */
  assert_near(satf_fiber_fresnel(-0.5f, 1.55f), 1.0, 0);
  /* from inside at the refracted angle of cos_i = 0.8: the same as outside */
  double sin_t = 0.6 / 1.55, cos_t = sqrt(1 - sin_t * sin_t);
  assert_near(satf_fiber_fresnel(-(float)cos_t, 1.55f),
              satf_fiber_fresnel(0.8f, 1.55f), 1e-6);
}

/* int M_p(theta_i, theta_o) cos(theta_i) d theta_i = 1 (d'Eon eq. 7's
 * normalisation) for variances from beta_m = 0.05 to 1, both forms. */
static void mp_normalised(void **state) {
  (void)state;
  const float betas[] = {0.05f, 0.1f, 0.2f, 0.3f, 0.45f, 0.6f, 0.8f, 1.0f};
  const double thetas[] = {-1.5, -1.0, -0.4, 0.0, 0.3, 0.9, 1.45};
  const int n = 20000;
  for (size_t b = 0; b < sizeof betas / sizeof *betas; b++)
    for (int mul = 0; mul < 3; mul++) {
      float v =
          satf_fiber_longitudinal_variance(betas[b]) * (mul == 0   ? 0.25f
                                                        : mul == 1 ? 1.0f
                                                                   : 4.0f);
      for (size_t t = 0; t < sizeof thetas / sizeof *thetas; t++) {
        double sum = 0;
        for (int i = 0; i < n; i++) {
          double ti = -SATF_PI / 2 + SATF_PI * (i + 0.5) / n;
          sum += satf_fiber_mp((float)cos(ti), (float)cos(thetas[t]),
                               (float)sin(ti), (float)sin(thetas[t]), v) *
                 cos(ti);
        }
        sum *= SATF_PI / n;
        if (fabs(sum - 1) > 1e-3)
          fprintf(stderr, "beta_m %g v %g theta_o %g: %g\n", betas[b], v,
                  thetas[t], sum);
        assert_near(sum, 1.0, 1e-3);
      }
    }
}

/* The trimmed logistic integrates to 1 on [-pi, pi] and its sampling is
 * its inverse CDF. */
static void logistic_normalised_and_sampled(void **state) {
  (void)state;
  const float scales[] = {0.02f, 0.1f, 0.3f, 0.7f, 1.5f, 3.0f};
  const int n = 40000;
  for (size_t k = 0; k < sizeof scales / sizeof *scales; k++) {
    float s = scales[k];
    double sum = 0;
    for (int i = 0; i < n; i++)
      sum += satf_fiber_trimmed_logistic(
          (float)(-SATF_PI + 2 * SATF_PI * (i + 0.5) / n), s);
    assert_near(sum * 2 * SATF_PI / n, 1.0, 1e-4);
    for (double u = 0.05; u < 1; u += 0.15) {
      float x = satf_fiber_sample_trimmed_logistic((float)u, s);
      double cdf = 0;
      for (int i = 0; i < n; i++) {
        double y = -SATF_PI + (x + SATF_PI) * (i + 0.5) / n;
        cdf += satf_fiber_trimmed_logistic((float)y, s);
      }
      assert_near(cdf * (x + SATF_PI) / n, u, 1e-3);
    }
  }
}

/* 2-D white furnace: no absorption, the in-plane scattering of one fibre,
 * sum over p of A_p(h) N_p integrated over phi and averaged over h, is 1;
 * in the normal plane (theta_o = 0) and on tilted cones. */
static void white_furnace_2d(void **state) {
  (void)state;
  const float beta_ns[] = {0.05f, 0.2f, 0.3f, 0.6f, 1.0f};
  const double theta_os[] = {0.0, 0.4, -1.0};
  const int nh = 400, nphi = 4000;
  for (size_t b = 0; b < sizeof beta_ns / sizeof *beta_ns; b++)
    for (size_t t = 0; t < sizeof theta_os / sizeof *theta_os; t++) {
      float s = satf_fiber_azimuthal_scale(beta_ns[b]);
      float sin_to = (float)sin(theta_os[t]), cos_to = (float)cos(theta_os[t]);
      float etap = satf_fiber_eta_prime(1.55f, sin_to);
      double total = 0;
      for (int j = 0; j < nh; j++) {
        float h = (float)(-1 + 2 * (j + 0.5) / nh);
        float ap[SATF_FIBER_LOBES];
        float T = satf_fiber_transmittance(0.0f, h, 1.55f, sin_to);
        assert_near(T, 1.0, 0);
        satf_fiber_ap(cos_to, 1.55f, h, T, ap);
        float gamma_o = asinf(h), gamma_t = asinf(h / etap);
        double e = 0;
        for (int i = 0; i < nphi; i++) {
          float phi = (float)(-SATF_PI + 2 * SATF_PI * (i + 0.5) / nphi);
          for (int p = 0; p < 3; p++)
            e += ap[p] * satf_fiber_np(phi, p, s, gamma_o, gamma_t);
          e += ap[3] / (2 * SATF_PI);
        }
        total += e * 2 * SATF_PI / nphi;
      }
      total /= nh;
      assert_near(total, 1.0, 1e-3);
    }
}

/* 3-D white furnace (pbrt's WhiteFurnace, here by quadrature): with
 * sigma_a = 0 the BCSDF integrated over the sphere of incident directions
 * is 1 within 1e-3, for beta_m >= 0.1 and every beta_n, with and without
 * the cuticle tilt (applied to theta_o, M_p stays normalised). */
static double sphere_integral(const satf_fiber *f, const float wo[3], float h,
                              int nt, int np) {
  double sum = 0;
  for (int i = 0; i < nt; i++) {
    double ti = -SATF_PI / 2 + SATF_PI * (i + 0.5) / nt;
    double row = 0;
    for (int j = 0; j < np; j++) {
      float wi[3], out[3];
      unit_dir(ti, -SATF_PI + 2 * SATF_PI * (j + 0.5) / np, wi);
      satf_fiber_eval(f, wo, wi, h, out);
      row += out[1];
    }
    sum += row * cos(ti);
  }
  return sum * (SATF_PI / nt) * (2 * SATF_PI / np);
}

static void white_furnace_3d(void **state) {
  (void)state;
  const float zero[3] = {0, 0, 0};
  const float beta_ms[] = {0.1f, 0.3f, 0.6f, 0.9f};
  const float beta_ns[] = {0.1f, 0.3f, 0.6f, 0.9f};
  const double theta_os[] = {0.35, -0.9};
  const float hs[] = {0.3f, -0.85f};
  for (size_t a = 0; a < sizeof beta_ms / sizeof *beta_ms; a++)
    for (size_t b = 0; b < sizeof beta_ns / sizeof *beta_ns; b++)
      for (int k = 0; k < 2; k++) {
        float wo[3];
        unit_dir(theta_os[k], 0.7 + k, wo);
        satf_fiber f;
        satf_fiber_init_sigma_a(&f, zero, beta_ms[a], beta_ns[b], 0.0f, 1.55f);
        double e = sphere_integral(&f, wo, hs[k], 500, 600);
        if (fabs(e - 1) > 1e-3)
          fprintf(stderr, "beta_m %g beta_n %g: %g\n", beta_ms[a], beta_ns[b],
                  e);
        assert_near(e, 1.0, 1e-3);
        satf_fiber_init_sigma_a(&f, zero, beta_ms[a], beta_ns[b],
                                (float)(2 * SATF_PI / 180), 1.55f);
        e = sphere_integral(&f, wo, hs[k], 500, 600);
        assert_near(e, 1.0, 1e-3);
      }
  /* with absorption strictly less */
  satf_fiber f;
  satf_fiber_material m = satf_fiber_material_default();
  satf_fiber_init(&f, &m);
  float wo[3];
  unit_dir(0.2, 1.0, wo);
  assert_true(sphere_integral(&f, wo, 0.1f, 300, 300) < 0.9);
}

/* Reciprocity: M_p is symmetric in i and o; without tilt the BCSDF is
 * reciprocal when |theta_i| = |theta_o| with the ray's mirrored offset
 * (swapping the directions mirrors the cross-section). pbrt's pointwise
 * Reciprocity test is disabled: the model is not reciprocal for unequal
 * inclinations (eta' and A_p depend on theta_o only). */
static void reciprocity(void **state) {
  (void)state;
  for (int i = 0; i < 200; i++) {
    double ti = -1.5 + 3.0 * ((i * 37) % 200) / 200.0;
    double to = -1.5 + 3.0 * ((i * 91 + 13) % 200) / 200.0;
    float v = 0.002f + 0.5f * (float)((i * 53) % 200) / 200.0f;
    float a = satf_fiber_mp((float)cos(ti), (float)cos(to), (float)sin(ti),
                            (float)sin(to), v);
    float b = satf_fiber_mp((float)cos(to), (float)cos(ti), (float)sin(to),
                            (float)sin(ti), v);
    assert_near(a, b, 1e-6 * fabs(a) + 1e-30);
  }
  const float sig[3] = {0.2f, 0.5f, 1.4f};
  satf_fiber f;
  satf_fiber_init_sigma_a(&f, sig, 0.3f, 0.35f, 0.0f, 1.55f);
  for (int i = 0; i < 100; i++) {
    double th = -1.4 + 2.8 * (i % 10) / 10.0;
    double po = -3.0 + 6.0 * ((i * 7) % 100) / 100.0;
    double pi = -3.0 + 6.0 * ((i * 31 + 5) % 100) / 100.0;
    float h = -0.95f + 1.9f * (float)((i * 17) % 100) / 100.0f;
    float wo[3], wi[3], a[3], b[3];
    unit_dir(th, po, wo);
    unit_dir(i % 2 ? th : -th, pi, wi);
    satf_fiber_eval(&f, wo, wi, h, a);
    satf_fiber_eval(&f, wi, wo, -h, b);
    for (int c = 0; c < 3; c++)
      assert_near(a[c], b[c], 1e-4 * fabs(a[c]) + 1e-7);
  }
}

/* No NaN, no infinity, no negative value over a dense sweep of the
 * parameters, including grazing and along-the-fibre directions and h at
 * the edges. */
static void sweep_finite_non_negative(void **state) {
  (void)state;
  const float melanins[] = {0.0f, 0.5f, 0.99f, 1.0f};
  const float betas[] = {0.0f, 0.01f, 0.1f, 0.3f, 0.7f, 1.0f};
  const float hs[] = {-1.0f, -0.999f, -0.5f, 0.0f, 0.5f, 0.999f, 1.0f};
  const double thetas[] = {-SATF_PI / 2, -1.2, -0.3, 0.0, 0.7, SATF_PI / 2};
  long n = 0;
  for (size_t m = 0; m < 4; m++)
    for (size_t bm = 0; bm < 6; bm++)
      for (size_t bn = 0; bn < 6; bn++)
        for (int tilt = 0; tilt < 2; tilt++) {
          satf_fiber_material mat = satf_fiber_material_default();
          mat.melanin = melanins[m];
          mat.redness = 0.3f;
          mat.roughness = betas[bm];
          mat.radial_roughness = betas[bn];
          mat.cuticle_tilt = tilt ? 0.1f : 0.0f;
          satf_fiber f;
          satf_fiber_init(&f, &mat);
          for (size_t hi = 0; hi < 7; hi++)
            for (size_t a = 0; a < 6; a++)
              for (size_t b = 0; b < 6; b++)
                for (int k = 0; k < 4; k++) {
                  float wo[3], wi[3], out[SATF_FIBER_LOBES][3];
                  unit_dir(thetas[a], 0.3 + k, wo);
                  unit_dir(thetas[b], -2.0 + 1.7 * k, wi);
                  satf_fiber_eval_lobes(&f, wo, wi, hs[hi], out);
                  for (int p = 0; p < SATF_FIBER_LOBES; p++)
                    for (int c = 0; c < 3; c++) {
                      if (!isfinite(out[p][c]) || out[p][c] < 0)
                        fprintf(stderr, "p %d: %g\n", p, out[p][c]);
                      assert_true(isfinite(out[p][c]) && out[p][c] >= 0);
                    }
                  n++;
                }
        }
  assert_true(n > 50000);
}

/* An independent geometric-optics trace of a smooth cylinder (radius 1,
 * axis x) in 3-D: the ray from wo at offset h refracts with the true index
 * eta (Snell in vector form, no Bravais index), reflects inside p - 1
 * times, leaves; its weight is the Fresnel factors at the actual incidence
 * angles times exp(-sigma_a * the actual path length). Gives the exit
 * direction and the weight of lobe p. */
static void reflect3(const double d[3], const double n[3], double out[3]) {
  double k = 2 * (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]);
  for (int i = 0; i < 3; i++)
    out[i] = d[i] - k * n[i];
}

/* d travelling into the surface with normal n facing d's origin side;
 * eta = n_after / n_before. Returns the Fresnel reflectance. */
static double refract3(const double d[3], const double n[3], double eta,
                       double out[3]) {
  double ci = -(d[0] * n[0] + d[1] * n[1] + d[2] * n[2]);
  double r = 1 / eta, k = 1 - r * r * (1 - ci * ci);
  if (k < 0)
    return 1;
  double ct = sqrt(k);
  for (int i = 0; i < 3; i++)
    out[i] = r * d[i] + (r * ci - ct) * n[i];
  double rs = (ci - eta * ct) / (ci + eta * ct);
  double rp = (eta * ci - ct) / (eta * ci + ct);
  return 0.5 * (rs * rs + rp * rp);
}

static double trace_cylinder(const double wo[3], double h, int p,
                             double sigma_a, double eta, double exit[3]) {
  /* the hit point: offset h along (sin phi_o, -cos phi_o) in the y-z plane,
   * on the near side */
  double po = atan2(wo[2], wo[1]);
  double ey = sin(po), ez = -cos(po);
  double cy = cos(po), cz = sin(po); /* towards the viewer */
  double k = sqrt(1 - h * h);
  double pos[3] = {0, h * ey + k * cy, h * ez + k * cz};
  double n[3] = {0, pos[1], pos[2]};
  double d[3] = {-wo[0], -wo[1], -wo[2]};
  if (p == 0) {
    double t[3];
    double fr = refract3(d, n, eta, t);
    reflect3(d, n, exit);
    return fr;
  }
  double t[3];
  double w = 1 - refract3(d, n, eta, t);
  for (int bounce = 0; bounce < p; bounce++) {
    /* to the far side of the circle: |pos + s t|_yz = 1 */
    double a = t[1] * t[1] + t[2] * t[2];
    double b = 2 * (pos[1] * t[1] + pos[2] * t[2]);
    double s = -b / a; /* pos is on the circle */
    for (int i = 0; i < 3; i++)
      pos[i] += s * t[i];
    w *= exp(-sigma_a * s * sqrt(t[0] * t[0] + a));
    double nin[3] = {0, -pos[1], -pos[2]}; /* facing the inside */
    double out[3];
    double fr = refract3(t, nin, 1 / eta, out);
    if (bounce == p - 1) {
      w *= 1 - fr;
      for (int i = 0; i < 3; i++)
        exit[i] = out[i];
    } else {
      w *= fr;
      double r[3];
      reflect3(t, nin, r);
      for (int i = 0; i < 3; i++)
        t[i] = r[i];
    }
  }
  return w;
}

/* Per lobe, the h-averaged azimuthal distribution of the library,
 * 1/2 int A_p(h) N_p(phi; h) dh (read from satf_fiber_eval_lobes divided by
 * M_p, so the whole lobe evaluation is under test), against the same
 * smoothing of the traced cylinder's exits, 1/2 int w_p(h)
 * D_s(phi - phi_exit(h)) dh. The trace also checks that the exits stay on
 * the specular cone (theta_i = -theta_o). */
static void lobes_match_traced_cylinder(void **state) {
  (void)state;
  const double theta_os[] = {0.0, 0.45, -0.8};
  const float sigma = 0.4f;
  const float sig3[3] = {sigma, sigma, sigma};
  satf_fiber f;
  satf_fiber_init_sigma_a(&f, sig3, 0.3f, 0.3f, 0.0f, 1.55f);
  const int nh = 4000, nphi = 48;
  for (size_t t = 0; t < sizeof theta_os / sizeof *theta_os; t++) {
    double to = theta_os[t], po = 0.9;
    double wo_d[3] = {sin(to), cos(to) * cos(po), cos(to) * sin(po)};
    float wo[3] = {(float)wo_d[0], (float)wo_d[1], (float)wo_d[2]};
    for (int p = 0; p < 3; p++) {
      double lib[48] = {0}, geo[48] = {0}, peak = 0;
      float mp = satf_fiber_mp((float)cos(to), (float)cos(to), (float)-sin(to),
                               (float)sin(to), f.v[p]);
      for (int j = 0; j < nh; j++) {
        double h = -1 + 2 * (j + 0.5) / nh;
        double ex[3];
        double w = trace_cylinder(wo_d, h, p, sigma, 1.55, ex);
        assert_near(ex[0], -wo_d[0], 1e-9); /* the specular cone */
        double phi_exit = atan2(ex[2], ex[1]) - po;
        for (int i = 0; i < nphi; i++) {
          double phi = -SATF_PI + 2 * SATF_PI * (i + 0.5) / nphi;
          float wi[3], out[SATF_FIBER_LOBES][3];
          unit_dir(-to, po + phi, wi);
          satf_fiber_eval_lobes(&f, wo, wi, (float)h, out);
          lib[i] += out[p][0] / mp / nh * 2 / 2;
          double d = remainder(phi - phi_exit, 2 * SATF_PI);
          geo[i] += w * satf_fiber_trimmed_logistic((float)d, f.s) / nh;
        }
      }
      for (int i = 0; i < nphi; i++)
        peak = fmax(peak, geo[i]);
      assert_true(peak > 1e-3);
      for (int i = 0; i < nphi; i++) {
        if (fabs(lib[i] - geo[i]) > 2e-3 * peak)
          fprintf(stderr, "theta_o %g p %d bin %d: %g vs %g\n", to, p, i,
                  lib[i], geo[i]);
        assert_near(lib[i], geo[i], 2e-3 * peak);
      }
    }
  }
}

/* Golden values from test_fiber_golden.py (an independent double-precision
 * implementation of the papers' formulas with mpmath's I0 and sinh). */
static void golden_values(void **state) {
  (void)state;
  static const struct {
    float to, po, ti, pi, h, melanin, redness, bm, bn, alpha_deg;
    float rgb[3];
  } cases[] = {
      {0.3f,
       1.5708f,
       -0.25f,
       1.2f,
       0.2f,
       0.6f,
       0.0f,
       0.3f,
       0.3f,
       2.0f,
       {0.1324194f, 0.1319045f, 0.131708f}},
      {-0.5f,
       0.4f,
       0.45f,
       3.0f,
       -0.7f,
       0.2f,
       0.5f,
       0.25f,
       0.4f,
       2.0f,
       {0.01833051f, 0.01596428f, 0.01117271f}},
      {0.1f,
       1.0f,
       0.2f,
       -2.5f,
       0.0f,
       0.0f,
       0.0f,
       0.5f,
       0.6f,
       0.0f,
       {0.4058347f, 0.4058347f, 0.4058347f}},
      {0.8f,
       -1.2f,
       -0.7f,
       2.1f,
       0.9f,
       0.9f,
       0.2f,
       0.15f,
       0.2f,
       3.0f,
       {4.570925e-05f, 3.275312e-05f, 3.264735e-05f}},
  };
  for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
    satf_fiber_material m = satf_fiber_material_default();
    m.melanin = cases[k].melanin;
    m.redness = cases[k].redness;
    m.roughness = cases[k].bm;
    m.radial_roughness = cases[k].bn;
    m.cuticle_tilt = cases[k].alpha_deg * (float)(SATF_PI / 180);
    satf_fiber f;
    satf_fiber_init(&f, &m);
    float wo[3], wi[3], out[3];
    unit_dir(cases[k].to, cases[k].po, wo);
    unit_dir(cases[k].ti, cases[k].pi, wi);
    satf_fiber_eval(&f, wo, wi, cases[k].h, out);
    for (int c = 0; c < 3; c++)
      assert_near(out[c], cases[k].rgb[c], 2e-4 * cases[k].rgb[c]);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(melanin_matches_cycles),
      cmocka_unit_test(fresnel_limits),
      cmocka_unit_test(mp_normalised),
      cmocka_unit_test(logistic_normalised_and_sampled),
      cmocka_unit_test(white_furnace_2d),
      cmocka_unit_test(white_furnace_3d),
      cmocka_unit_test(reciprocity),
      cmocka_unit_test(sweep_finite_non_negative),
      cmocka_unit_test(lobes_match_traced_cylinder),
      cmocka_unit_test(golden_values),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
