/* fiber.glsl - the hair fibre model of common/fiber.c and
 * common/fiber_dual.c in GLSL (no #version: included by shaders, and
 * evaluated alone by tests/render/test_fiber_glsl.c against the C): d'Eon
 * et al. 2011's M_p and A_p, Chiang et al. 2016's logistic N_p, Cycles'
 * parameter meanings and tilt direction, and the dual scattering of Zinke
 * et al. 2008 from the tables of satf_fiber_dual_tables.
 *
 * Frame (satf/fiber.h, pbrt's): x along the fibre, sin(theta) = w.x,
 * phi = atan(w.z, w.y); h in [-1, 1] the offset of the ray from wo across
 * the fibre. Everything returned is radiance per unit irradiance (a
 * directional light's irradiance E, perpendicular to it, gives L = E f). */
const float FIBER_PI = 3.14159265358979;

struct Fiber {
  float eta;
  vec4 v;        /* M_p variances of R, TT, TRT, the remainder */
  float s;       /* N_p logistic scale */
  vec3 sigma_a;  /* per unit fibre radius */
  float alpha;   /* cuticle tilt, radians */
};

/* atan(y, x) and asin to ~1e-7 rad: N_p multiplies angle errors by 1 / s
 * (up to 40 for smooth hair), and drivers' atan and asin are allowed far
 * less accuracy (Mesa's llvmpipe's left 2% in the lobes). */
float fiber_atan_unit(float z) { /* |z| <= tan(pi / 8) */
  float z2 = z * z;
  return z * (1.0 + z2 * (-0.33333333 + z2 * (0.2 + z2 * (-0.14285714 +
         z2 * (0.11111111 + z2 * (-0.09090909 + z2 * 0.07692308))))));
}
float fiber_atan2(float y, float x) {
  float ax = abs(x), ay = abs(y);
  float hi = max(ax, ay), lo = min(ax, ay);
  if (hi == 0.0) return 0.0;
  float z = lo / hi, a;
  /* atan z = pi / 4 + atan((z - 1) / (z + 1)) above tan(pi / 8) */
  if (z > 0.41421356) a = 0.78539816 + fiber_atan_unit((z - 1.0) / (z + 1.0));
  else a = fiber_atan_unit(z);
  if (ay > ax) a = 1.57079633 - a;
  if (x < 0.0) a = 3.14159265 - a;
  return y < 0.0 ? -a : a;
}
float fiber_asin(float x) {
  x = clamp(x, -1.0, 1.0);
  return fiber_atan2(x, sqrt(max(1.0 - x * x, 0.0)));
}

float fiber_i0(float x) {
  float x2 = x * x, term = 1.0, sum = 1.0;
  for (int k = 1; k < 24; k++) {
    term *= x2 / (4.0 * float(k * k));
    sum += term;
    if (term < sum * 1e-8) break;
  }
  return sum;
}

float fiber_log_i0(float x) {
  if (x > 12.0) {
    float r = 1.0 / x;
    return x - 0.5 * log(2.0 * FIBER_PI * x) +
           log(1.0 + r * (0.125 + r * (0.0703125 + r * 0.0732421875)));
  }
  return log(fiber_i0(x));
}

/* d'Eon 2011 eq. 7; the log form for v <= 0.1 */
float fiber_mp(float cos_ti, float cos_to, float sin_ti, float sin_to,
               float v) {
  float a = cos_ti * cos_to / v, b = sin_ti * sin_to / v;
  if (v <= 0.1) return exp(fiber_log_i0(a) - b - 1.0 / v - log(v));
  return exp(-b) * fiber_i0(a) / (2.0 * v * sinh(1.0 / v));
}

float fiber_fresnel(float cos_i, float eta) {
  cos_i = clamp(cos_i, -1.0, 1.0);
  if (cos_i < 0.0) { eta = 1.0 / eta; cos_i = -cos_i; }
  float sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0) return 1.0;
  float cos_t = sqrt(max(1.0 - sin2_t, 0.0));
  float rpar = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  float rper = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5 * (rpar * rpar + rper * rper);
}

float fiber_phi(int p, float gamma_o, float gamma_t) {
  return 2.0 * float(p) * gamma_t - 2.0 * gamma_o + float(p) * FIBER_PI;
}

float fiber_logistic_cdf(float x, float s) {
  float arg = -x / s;
  return arg > 80.0 ? 0.0 : 1.0 / (1.0 + exp(arg));
}

float fiber_trimmed_logistic(float x, float s) {
  float e = exp(-abs(x) / s);
  return e / (s * (1.0 + e) * (1.0 + e)) /
         (1.0 - 2.0 * fiber_logistic_cdf(-FIBER_PI, s));
}

float fiber_wrap(float d) { /* to [-pi, pi) */
  return d - 2.0 * FIBER_PI * floor((d + FIBER_PI) / (2.0 * FIBER_PI));
}

/* Chiang 2016 eq. 10 */
float fiber_np(float phi, int p, float s, float gamma_o, float gamma_t) {
  return fiber_trimmed_logistic(fiber_wrap(phi - fiber_phi(p, gamma_o, gamma_t)),
                                s);
}

/* int over [phi0, phi0 + len] of N_p, len in [0, 2 pi] */
float fiber_np_integral(float phi0, float len, int p, float s, float gamma_o,
                        float gamma_t) {
  float lo = fiber_logistic_cdf(-FIBER_PI, s), k = 1.0 - 2.0 * lo;
  float a = fiber_wrap(phi0 - fiber_phi(p, gamma_o, gamma_t)), b = a + len;
  float ca = (fiber_logistic_cdf(a, s) - lo) / k;
  if (b <= FIBER_PI) return (fiber_logistic_cdf(b, s) - lo) / k - ca;
  return 1.0 - ca + (fiber_logistic_cdf(b - 2.0 * FIBER_PI, s) - lo) / k;
}

/* A_p for one channel, d'Eon 2011 eq. 12-14, T one internal pass */
vec4 fiber_ap(float cos_theta_o, float eta, float h, float T) {
  float f = fiber_fresnel(cos_theta_o * sqrt(max(1.0 - h * h, 0.0)), eta);
  float a1 = (1.0 - f) * (1.0 - f) * T, a2 = a1 * T * f, tf = T * f;
  return vec4(f, a1, a2, tf < 1.0 ? a2 * tf / (1.0 - tf) : 0.0);
}

float fiber_eta_prime(float eta, float sin_theta_o) {
  float c = max(sqrt(max(1.0 - sin_theta_o * sin_theta_o, 0.0)), 1e-6);
  return sqrt(max(eta * eta - sin_theta_o * sin_theta_o, 0.0)) / c;
}

/* theta_o rotated for lobe p (satf_fiber_tilt): R +2 alpha, TT -alpha,
 * TRT -4 alpha; returns (sin, |cos|) */
vec2 fiber_tilt(float alpha, int p, float sin_o, float cos_o) {
  float a = p == 0 ? 2.0 * alpha : p == 1 ? -alpha : p == 2 ? -4.0 * alpha : 0.0;
  float sa = sin(a), ca = cos(a);
  return vec2(sin_o * ca + cos_o * sa, abs(cos_o * ca - sin_o * sa));
}

/* The lobes' A_p (RGB) and the angles of wo and h, shared by the single
 * and the globally scattered terms. */
struct FiberGeom {
  float sin_o, cos_o, phi_o, gamma_o, gamma_t;
  vec4 ap[3]; /* per channel: A_0..A_3 */
};

FiberGeom fiber_geom(Fiber f, vec3 wo, float h) {
  FiberGeom g;
  h = clamp(h, -1.0, 1.0);
  g.sin_o = clamp(wo.x, -1.0, 1.0);
  g.cos_o = sqrt(max(1.0 - g.sin_o * g.sin_o, 0.0));
  g.phi_o = fiber_atan2(wo.z, wo.y);
  g.gamma_o = fiber_asin(h);
  g.gamma_t = fiber_asin(clamp(h / fiber_eta_prime(f.eta, g.sin_o), -1.0, 1.0));
  float sin_t = g.sin_o / f.eta;
  float cos_t = sqrt(max(1.0 - sin_t * sin_t, 0.0));
  float path = 2.0 * cos(g.gamma_t) / cos_t;
  for (int c = 0; c < 3; c++)
    g.ap[c] = fiber_ap(g.cos_o, f.eta, h, exp(-f.sigma_a[c] * path));
  return g;
}

/* lobe p of the BCSDF, RGB */
vec3 fiber_lobe(Fiber f, FiberGeom g, vec3 wi, int p) {
  float sin_i = clamp(wi.x, -1.0, 1.0);
  float cos_i = sqrt(max(1.0 - sin_i * sin_i, 0.0));
  vec2 o = fiber_tilt(f.alpha, p, g.sin_o, g.cos_o);
  float mp = fiber_mp(cos_i, o.y, sin_i, o.x, f.v[p]);
  float np = p < 3 ? fiber_np(fiber_atan2(wi.z, wi.y) - g.phi_o, p, f.s, g.gamma_o,
                              g.gamma_t)
                   : 0.5 / FIBER_PI;
  return mp * np * vec3(g.ap[0][p], g.ap[1][p], g.ap[2][p]);
}

/* The single-scattering BCSDF sum_p M_p A_p N_p (satf_fiber_eval), RGB */
vec3 fiber_single(Fiber f, vec3 wo, vec3 wi, float h) {
  FiberGeom g = fiber_geom(f, wo, h);
  vec3 sum = vec3(0.0);
  for (int p = 0; p < 4; p++) sum += fiber_lobe(f, g, wi, p);
  return sum;
}

/* One field of the dual-scattering tables (satf_fiber_dual_tables: an
 * RGB texture SATF_FIBER_DUAL_FIELDS wide, one row per |theta| bin),
 * linear in |theta| between the bin centres. */
vec3 fiber_dual_field(sampler2D tab, int field, float theta) {
  int n = textureSize(tab, 0).y;
  float x = clamp(abs(theta) / (0.5 * FIBER_PI) * float(n) - 0.5, 0.0,
                  float(n - 1));
  int k = min(int(x), max(n - 2, 0));
  float t = n > 1 ? x - float(k) : 0.0;
  vec3 a = texelFetch(tab, ivec2(field, k), 0).rgb;
  vec3 b = texelFetch(tab, ivec2(field, min(k + 1, n - 1)), 0).rgb;
  return mix(a, b, t);
}

/* Zinke's density factors d_f = d_b: a choice, the paper's 0.7
 * (SATF_FIBER_DUAL_DENSITY says why and what it measured) */
const float FIBER_DUAL_DENSITY = 0.7;

/* The BCSDF of the globally (forward) scattered light of Zinke 2008 at a
 * point n_hairs hairs deep: d_f (f_s^G + d_b f_back^G) (eq. 23-25), which
 * fiber_dual_shade weighs by the scattered transmittance; with `back` the
 * direct light's local back-scattering f_back (eq. 10, 15). */
vec3 fiber_dual_global(Fiber f, sampler2D tab, FiberGeom g, vec3 wi,
                       float n_hairs, out vec3 back) {
  float sin_i = clamp(wi.x, -1.0, 1.0);
  float theta_i = fiber_asin(sin_i), cos_i = cos(theta_i);
  float theta_o = fiber_asin(g.sin_o);
  float n = max(n_hairs, 0.0);
  vec3 beta_f2 = fiber_dual_field(tab, 4, theta_i);
  float phi_i = fiber_atan2(wi.z, wi.y);
  float dphi = abs(fiber_wrap(phi_i - g.phi_o));
  /* local back-scattering (eq. 10, 15; satf_fiber_dual_back) */
  float theta_d = 0.5 * (theta_o - theta_i);
  vec3 ab = fiber_dual_field(tab, 6, theta_d);
  vec3 delta = fiber_dual_field(tab, 7, theta_d);
  vec3 sb2 = fiber_dual_field(tab, 8, theta_d);
  vec3 back_g = vec3(0.0);
  back = vec3(0.0);
  vec3 sf2 = max(n, 1.0) * beta_f2;
  for (int c = 0; c < 3; c++) {
    float tc = theta_o - delta[c];
    float v = max(sb2[c], 1e-4);
    if (dphi < 0.5 * FIBER_PI)
      back[c] = ab[c] * fiber_mp(cos_i, abs(cos(tc)), sin_i, sin(tc), v) /
                FIBER_PI;
    /* under the arriving half-circle: the overlap of the two half-circles
     * over pi^2 */
    back_g[c] = ab[c] *
                fiber_mp(cos_i, abs(cos(tc)), sin_i, sin(tc), v + sf2[c]) *
                (FIBER_PI - dphi) / (FIBER_PI * FIBER_PI);
  }
  vec3 single_g = vec3(0.0);
  for (int p = 0; p < 4; p++) {
    vec2 o = fiber_tilt(f.alpha, p, g.sin_o, g.cos_o);
    float ng = p < 3 ? fiber_np_integral(phi_i - 0.5 * FIBER_PI - g.phi_o,
                                         FIBER_PI, p, f.s, g.gamma_o,
                                         g.gamma_t) /
                           FIBER_PI
                     : 0.5 / FIBER_PI;
    for (int c = 0; c < 3; c++)
      single_g[c] += fiber_mp(cos_i, o.y, sin_i, o.x, f.v[p] + sf2[c]) * ng *
                     g.ap[c][p];
  }
  return FIBER_DUAL_DENSITY * (single_g + FIBER_DUAL_DENSITY * back_g);
}

/* Zinke's forward-scattered transmittance to a point n_hairs deep, less
 * the direct light's e^-n (eq. 5 averaged over a Poisson count). */
vec3 fiber_dual_scattered(sampler2D tab, vec3 wi, float n_hairs) {
  float n = max(n_hairs, 0.0);
  vec3 af = fiber_dual_field(tab, 0, fiber_asin(clamp(wi.x, -1.0, 1.0)));
  return max(exp(-n * (1.0 - af)) - exp(-n), vec3(0.0));
}

/* The shading of Zinke 2008's dual scattering (its sec. 4.2 algorithm, in
 * this normalisation; satf_fiber_dual_shade is the C twin), RGB radiance
 * per unit irradiance of a light towards wi, with n_hairs the expected
 * number of hairs a ray from the point to the light crosses (the deep
 * opacity map's summed coverage). The light reaches the point directly
 * with the probability e^-n (hairs crossed as a Poisson process) and
 * forward-scattered with the expected forward transmittance
 * e^-n(1 - a_f) (eq. 5 averaged over the Poisson count) less that; the
 * forward-scattered light arrives isotropically over the half-circle of
 * azimuths around the light's (eq. 7), its inclination spread by
 * sigma_f^2 = max(n, 1) beta_f^2 (eq. 8). Direct: f_s + d_b f_back
 * (eq. 20); scattered: d_f (f_s^G + d_b f_back^G) with the variances
 * widened (eq. 23-24) and N_p averaged over the arriving azimuths (eq. 25,
 * here exactly by N_p's CDF since h is known). */
vec3 fiber_dual_shade(Fiber f, sampler2D tab, vec3 wo, vec3 wi, float h,
                      float n_hairs) {
  FiberGeom g = fiber_geom(f, wo, h);
  vec3 back;
  vec3 global = fiber_dual_global(f, tab, g, wi, n_hairs, back);
  vec3 single = vec3(0.0);
  for (int p = 0; p < 4; p++) single += fiber_lobe(f, g, wi, p);
  return exp(-max(n_hairs, 0.0)) * (single + FIBER_DUAL_DENSITY * back) +
         fiber_dual_scattered(tab, wi, n_hairs) * global;
}
