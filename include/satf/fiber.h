/* fiber.h - the physically based hair fibre model of satf (the fiber
 * library, fiber/): d'Eon et al. 2011 (paper 003) with the Chiang et al.
 * 2016 roughness mappings, the parameter meanings of Blender Cycles'
 * Principled Hair BSDF (melanin mode) and pbrt-v4's HairBxDF, so a user sets
 * the same numbers in satf and in either peer. It owns the scattering
 * function of one fibre (longitudinal M_p, azimuthal N_p, attenuation A_p for
 * the lobes R, TT, TRT and the remainder) and the dual-scattering tables of
 * Zinke et al. 2008 (paper 004) computed from it.
 *
 * Frame (pbrt's): x along the fibre from root to tip, y and z span the
 * fibre's normal plane. A direction w has sin(theta) = w[0] and azimuth
 * phi = atan2(w[2], w[1]). h in [-1, 1] is where the ray from wo meets the
 * fibre's circular cross-section (radius 1): the hit point's coordinate
 * along (sin phi_o, -cos phi_o) in the y-z plane (for a viewer on +z, the
 * hit point's y), so gamma_o = asin(h).
 *
 * Units: sigma_a is an absorption coefficient per unit fibre radius (one
 * internal pass at h = 0, theta = 0 has length 2). The BCSDF S = sum_p M_p
 * A_p N_p is normalised as pbrt's and Cycles' (d'Eon's M_p integrates to 1
 * against cos(theta_i) d theta_i): a directional light of irradiance E
 * (measured perpendicular to the light, as a Cycles sun's strength) gives
 * the radiance L_o = E S(wo, wi) towards wo. With nothing absorbed,
 * int over the sphere of S d omega_i = 1 (pbrt's white furnace). */
#ifndef SATF_FIBER_H
#define SATF_FIBER_H

#ifdef __cplusplus
extern "C" {
#endif

/* The lobes: p = 0 R, 1 TT, 2 TRT, 3 the remainder p >= 3 (pbrt's pMax). */
#define SATF_FIBER_LOBES 4

/* Cycles' melanin mode (node "Principled Hair", parametrisation
 * "Melanin Concentration"; the random and tint inputs at their neutral
 * values): quantity = -log(max(1 - melanin, 1e-4)), eumelanin = q (1 -
 * redness), pheomelanin = q redness, sigma_a = eumelanin (0.506, 0.841,
 * 1.653) + pheomelanin (0.343, 0.733, 1.924) per unit fibre radius. These
 * are Cycles' RGB cross-sections (bsdf_principled_hair_sigma_from_
 * concentration); pbrt-v4's spectral d'Eon cross-sections, turned into RGB
 * by pbrt's own spectral upsampling, read (0.419, 0.697, 1.37) and (0.187,
 * 0.4, 1.05): satf_fiber_sigma_a_concentration_pbrt gives those. */
void satf_fiber_sigma_a_melanin(float melanin, float redness, float sigma_a[3]);

/* pbrt-v4's SigmaAFromConcentration(ce, cp): eumelanin ce and pheomelanin
 * cp concentrations with pbrt's cross-sections. */
void satf_fiber_sigma_a_concentration_pbrt(float eumelanin, float pheomelanin,
                                           float sigma_a[3]);

/* Chiang et al. 2016 eq. 7: the variance v of M_0 (the R lobe) for the
 * longitudinal roughness beta_m in [0, 1]; the lobes use v[0] = v,
 * v[1] = v / 4, v[2] = v[3] = 4 v (pbrt, Cycles). */
float satf_fiber_longitudinal_variance(float beta_m);

/* Chiang et al. 2016 eq. 8: the logistic scale s of N_p for the azimuthal
 * (radial) roughness beta_n in [0, 1]. */
float satf_fiber_azimuthal_scale(float beta_n);

/* Unpolarised Fresnel reflectance of a dielectric of relative index eta for
 * light arriving at cos_theta_i from outside (negative: from inside). */
float satf_fiber_fresnel(float cos_theta_i, float eta);

/* d'Eon 2011 eq. 7: M_p(theta_i, theta_o) = csch(1/v) / (2 v)
 * exp(-sin_ti sin_to / v) I0(cos_ti cos_to / v), normalised so that
 * int M_p cos(theta_i) d theta_i = 1 over [-pi/2, pi/2]; for v <= 0.1 in the
 * log-I0 form (d'Eon's appendix) that does not overflow. Symmetric in i, o. */
float satf_fiber_mp(float cos_ti, float cos_to, float sin_ti, float sin_to,
                    float v);

/* The exit azimuth of lobe p relative to the entry (d'Eon 2011 eq. 9,
 * Marschner 2003 eq. 3): 2 p gamma_t - 2 gamma_o + p pi. */
float satf_fiber_phi(int p, float gamma_o, float gamma_t);

/* The logistic distribution of scale s trimmed and renormalised to
 * [-pi, pi] (Chiang 2016 eq. 11); integrates to 1 over [-pi, pi]. */
float satf_fiber_trimmed_logistic(float x, float s);

/* Its inverse CDF: a sample in [-pi, pi] for u in [0, 1). */
float satf_fiber_sample_trimmed_logistic(float u, float s);

/* N_p(phi) of one offset h (Chiang 2016 eq. 10): the trimmed logistic
 * around the lobe's exit azimuth, phi = phi_i - phi_o; integrates to 1 over
 * any 2 pi interval. */
float satf_fiber_np(float phi, int p, float s, float gamma_o, float gamma_t);

/* A_p for one colour channel (d'Eon 2011 eq. 12-14 with pbrt's closed form
 * for the remainder): f = Fresnel(cos_theta_o cos_gamma_o, eta),
 * A_0 = f, A_1 = (1 - f)^2 T, A_2 = A_1 T f, A_3 = A_2 T f / (1 - T f), with T
 * the transmittance of one internal pass. sum_p A_p = 1 when T = 1. */
void satf_fiber_ap(float cos_theta_o, float eta, float h, float T,
                   float ap[SATF_FIBER_LOBES]);

/* T of one internal pass: exp(-sigma_a 2 cos(gamma_t) / cos(theta_t)), with
 * sin(theta_t) = sin(theta_o) / eta and sin(gamma_t) = h / eta', eta' =
 * sqrt(eta^2 - sin^2 theta_o) / cos(theta_o) (Bravais' index). */
float satf_fiber_transmittance(float sigma_a, float h, float eta,
                               float sin_theta_o);

/* Bravais' index eta' of the fibre's normal plane for sin(theta_o). */
float satf_fiber_eta_prime(float eta, float sin_theta_o);

/* The material in the peers' terms. */
typedef struct satf_fiber_material {
  float melanin;          /* [0, 1], Cycles' Melanin */
  float redness;          /* [0, 1], Cycles' Melanin Redness */
  float roughness;        /* beta_m in [0, 1], Cycles' Roughness */
  float radial_roughness; /* beta_n in [0, 1], Cycles' Radial Roughness */
  float cuticle_tilt;     /* alpha, radians; Cycles' Offset (2 degrees) */
  float ior;              /* eta, 1.55 */
} satf_fiber_material;

/* Cycles' node defaults except melanin (0.8 there; 0.6 here, the issue's
 * brown) and redness (1.0 there; 0 here, a neutral brown): melanin 0.6,
 * redness 0, roughness 0.3, radial roughness 0.3, tilt 2 degrees, ior
 * 1.55. */
satf_fiber_material satf_fiber_material_default(void);

/* The prepared fibre: what every evaluation needs, computed once. */
typedef struct satf_fiber {
  float eta;
  float v[SATF_FIBER_LOBES]; /* M_p variances */
  float s;                   /* N_p logistic scale */
  float sigma_a[3];          /* RGB, per unit radius */
  float alpha;               /* cuticle tilt, radians */
  /* sin and cos of 2^k alpha, k = 0, 1, 2: the lobes' longitudinal shifts
   * (TT by alpha, R by 2 alpha, TRT by 4 alpha, Marschner 2003 Table 1). */
  float sin_2k_alpha[3], cos_2k_alpha[3];
} satf_fiber;

/* From the material (sigma_a from melanin and redness). */
void satf_fiber_init(satf_fiber *f, const satf_fiber_material *m);

/* From an RGB absorption coefficient directly (Cycles' "Absorption
 * Coefficient" mode, pbrt's sigma_a). */
void satf_fiber_init_sigma_a(satf_fiber *f, const float sigma_a[3],
                             float beta_m, float beta_n, float alpha,
                             float eta);

/* The cuticle tilt of lobe p (Marschner 2003 Table 1 shifts; p = 3 is not
 * shifted), applied as pbrt-v4 applies it, to theta_o, which keeps M_p
 * normalised (the white furnace holds with a tilt), in the direction
 * Cycles' Offset shifts its lobes: M_0 is evaluated at theta_o + 2 alpha,
 * M_1 at theta_o - alpha, M_2 at theta_o - 4 alpha. So the R highlight
 * peaks near theta_i = -theta_o - 2 alpha, as Cycles' (which rotates
 * theta_i by the same amounts instead): with x from root to tip and
 * alpha > 0 it moves towards the root, Marschner's alpha_R = -2 alpha.
 * pbrt-v4 rotates theta_o the other way (its alpha is this one negated).
 * cos_p is returned non-negative. */
void satf_fiber_tilt(const satf_fiber *f, int p, float sin_theta_o,
                     float cos_theta_o, float *sin_p, float *cos_p);

/* The BCSDF per lobe: out[p][c] = M_p A_p N_p for lobe p, channel c (the
 * remainder with N_3 = 1 / (2 pi)). wo, wi unit vectors in the fibre frame
 * above, h in [-1, 1]. */
void satf_fiber_eval_lobes(const satf_fiber *f, const float wo[3],
                           const float wi[3], float h,
                           float out[SATF_FIBER_LOBES][3]);

/* The BCSDF: out = sum_p M_p A_p N_p (RGB). */
void satf_fiber_eval(const satf_fiber *f, const float wo[3], const float wi[3],
                     float h, float out[3]);

/* int over [phi0, phi1] of N_p(phi) (phi1 - phi0 in [0, 2 pi]), from the
 * trimmed logistic's CDF with N_p's 2 pi periodicity. */
float satf_fiber_np_integral(float phi0, float phi1, int p, float s,
                             float gamma_o, float gamma_t);

/* Dual scattering (Zinke et al. 2008, paper 004): per inclination bin and
 * RGB channel, from the fibre's own lobes. Bin k of n holds |theta| =
 * (k + 0.5) / n * pi / 2, the inclination of the light at the scattering
 * fibre (the tables are even in theta). The shifts are of theta_i +
 * theta_o (radians, the convention of satf_fiber_tilt: R -2 alpha, TT
 * +alpha, TRT +4 alpha, the remainder 0); the variances are d'Eon's v_p
 * (beta_p^2). a_f and a_b are eq. 6 and 12 as written: the light arrives
 * isotropically over the half-circle of azimuths around the shadow path
 * (the forward-scattered light of eq. 7), forward is the half of the
 * normal plane that goes on along the path, backward the half that
 * returns (so a ray arriving off the path that a wide TT lobe turns
 * round counts as returned). The local back-scattering A_b, Delta_b,
 * sigma_b^2 (eq. 11-17) count hair crossings as the Poisson process of the
 * global term (satf_fiber_dual_shade): fiber_dual.c derives them. */
enum {
  SATF_FIBER_DUAL_AF = 0,   /* a_f: forward-scattered fraction, eq. 6 */
  SATF_FIBER_DUAL_AB,       /* a_b: backward-scattered fraction, eq. 12 */
  SATF_FIBER_DUAL_ALPHA_F,  /* alpha_f: mean forward shift */
  SATF_FIBER_DUAL_ALPHA_B,  /* alpha_b: mean backward shift */
  SATF_FIBER_DUAL_BETA_F2,  /* beta_f^2: mean forward variance */
  SATF_FIBER_DUAL_BETA_B2,  /* beta_b^2: mean backward variance */
  SATF_FIBER_DUAL_A_B,      /* A_b = A_1 + A_3 (eq. 14; 11, 13 Poisson) */
  SATF_FIBER_DUAL_DELTA_B,  /* Delta_b: mean shift (eq. 16's role) */
  SATF_FIBER_DUAL_SIGMA_B2, /* sigma_b^2: variance (eq. 17's role) */
  SATF_FIBER_DUAL_FIELDS
};

/* Zinke's density factors d_f = d_b (eq. 5, 9): a choice, 0.7, the paper's
 * value for all its images (sec. 3.1.1; Fig. 13: 0.6-0.8 match path
 * tracing for most hair styles). They stand for the part of a point's
 * surroundings that holds hair: a semi-infinite slab of fibres would take
 * d_b = 1 (test_fiber_slab), a hair volume with gaps and edges less.
 * Measured on the ponytail against Cycles: front-lit luminance
 * 0.86 / 0.88 / 0.90 (clusters) and 1.00 / 1.03 / 1.05 (strands) at 0.6 /
 * 0.7 / 0.8, melanin 0.2 0.87-0.96 and 0.89-1.01. */
#define SATF_FIBER_DUAL_DENSITY 0.7f

/* Fills out[(k * SATF_FIBER_DUAL_FIELDS + field) * 3 + c] for k < n (so an
 * RGB texture of SATF_FIBER_DUAL_FIELDS x n texels), by quadrature over h
 * and the lobes' azimuthal CDFs. n >= 1. */
void satf_fiber_dual_tables(const satf_fiber *f, int n, float *out);

/* Linear interpolation of one field and channel of the tables at |theta|
 * (clamped to the bin centres). */
float satf_fiber_dual_lookup(const float *tables, int n, int field, int c,
                             float theta);

/* The local back-scattering BCSDF f_back (Zinke eq. 10, 15) in this
 * header's normalisation, one channel: A_b (1 / pi on the backward
 * half-circle |phi_i - phi_o| < pi / 2) times the longitudinal spread
 * around theta_i + theta_o = Delta_b of variance sigma_b^2 + extra_var,
 * looked up at theta_d = (theta_o - theta_i) / 2. The spread is Zinke's
 * Gaussian g(theta_i + theta_o - Delta_b) / cos(theta_d) written as d'Eon's
 * M_p of that variance (equal for narrow lobes, normalised on the sphere
 * for wide ones), so f_back integrates over omega_i to A_b (Zinke's factor
 * 2 in eq. 10 left out: A_b is already the returned fraction). extra_var
 * is the global spread sigma_f^2 when the light arrives forward-scattered
 * (eq. 24). */
float satf_fiber_dual_back(const float *tables, int n, int c, const float wo[3],
                           const float wi[3], float extra_var);

/* The shading of the dual scattering approximation (Zinke 2008 sec. 4.2
 * in this header's normalisation; online/render/glsl/fiber.glsl's
 * fiber_dual_shade is its GLSL twin): RGB radiance towards wo per unit
 * irradiance of a light towards wi, at offset h, with n_hairs the expected
 * number of hairs a ray from the point to the light crosses (a deep
 * opacity map's summed coverage). The light arrives directly with the
 * probability e^-n (a Poisson count of crossings), forward-scattered with
 * the expected forward transmittance e^-n(1 - a_f) (eq. 5 averaged over
 * that count) less the direct part, isotropic over the half-circle of
 * azimuths around the light's (eq. 7) and spread in inclination by
 * sigma_f^2 = max(n, 1) beta_f^2 (eq. 8). Direct: f_s + d_b f_back (eq.
 * 20); scattered: d_f (f_s^G + d_b f_back^G), the lobes' variances widened
 * by sigma_f^2 (eq. 23-24), N_p averaged over the arriving azimuths
 * exactly by its CDF (eq. 25, with h known). n_hairs = 0 gives f_s +
 * d_b f_back. */
void satf_fiber_dual_shade(const satf_fiber *f, const float *tables, int n,
                           const float wo[3], const float wi[3], float h,
                           float n_hairs, float out[3]);
/* The same with the direct part's d_b scaled by 1 - e^-n_behind for
 * n_behind hairs behind the point (away from the light), which send its
 * local back-scattering: what the strand path draws where the deep
 * opacity map counts them (a lone strand has none). satf_fiber_dual_shade
 * is n_behind = INFINITY, a point inside a hair volume. */
void satf_fiber_dual_shade_behind(const satf_fiber *f, const float *tables,
                                  int n, const float wo[3], const float wi[3],
                                  float h, float n_hairs, float n_behind,
                                  float out[3]);

/* What satf_fiber_dual_shade's light brings by way of other hairs, per
 * unit irradiance, without the Poisson factors of n_hairs: global, the
 * forward-scattered light's d_f (f_s^G + d_b f_back^G) (eq. 23-25), and
 * back, the direct light's local back-scattering f_back (eq. 10, 15); so
 * the shading is e^-n (f_s + d_b back) + (e^-n(1 - a_f) - e^-n) global.
 * online/render/glsl/fiber.glsl's fiber_dual_global is its GLSL twin. */
void satf_fiber_dual_global(const satf_fiber *f, const float *tables, int n,
                            const float wo[3], const float wi[3], float h,
                            float n_hairs, float global[3], float back[3]);

/* satf_fiber_dual_global at h = 0 and one hair, as the cluster path's
 * physical mode takes it per vertex (glsl/fiber_cluster.glsl), tabulated
 * in the fibre frame whose y axis is the view's direction across the hair
 * (wo = (sin theta_o, cos theta_o, 0)), over the coordinates of
 * satf_fiber_global_coords: RGB at the centres of NH x ND x NPHI bins,
 * entry ((k_phi ND + k_d) NH + k_h) 3 + c of each array, a 3-D texture for
 * GL to filter. Trilinear interpolation of it is within 2.5% of the
 * term's peak for |theta| <= 66 degrees, longitudinal roughness 0.15-0.3,
 * 4.4% at 72 (test_fiber_dual: global_table). 49K evaluations, on
 * `threads` threads (0: every core): 64 ms on one of this machine's. */
#define SATF_FIBER_GLOBAL_NH 48
#define SATF_FIBER_GLOBAL_ND 32
#define SATF_FIBER_GLOBAL_NPHI 32
void satf_fiber_dual_global_table(const satf_fiber *f, const float *tables,
                                  int n, int threads, float *global,
                                  float *back);
/* The table's coordinates in [0, 1]^3 of (theta_o, theta_i, phi_i), phi_i
 * the light's azimuth about the hair from the view's (the term is even in
 * it at h = 0). The lobes are ridges along theta_h = (theta_o +
 * theta_i) / 2 = their small shifts, as narrow as TT's deviation there,
 * and smooth in theta_d = (theta_o - theta_i) / 2; in phi_i the term
 * steps at |phi_i| = pi / 2, where the half-circle of arriving light
 * (eq. 7, 25) takes in or leaves the lobes' peaks (at h = 0 TT's at pi,
 * R's and TRT's at 0, each about the logistic scale s wide) and the
 * back-scattering's half-circle ends. So: theta_h and |phi_i| - pi / 2
 * warped as 1/2 + asinh(x / w) / (2 asinh(pi / 2w)), w half TT's
 * deviation sqrt(v_TT) / 2 (at least 0.02) and 2 s, bins of about w / 3
 * at the ridge or step and 15 degrees far from them; theta_d linear. */
void satf_fiber_global_coords(const satf_fiber *f, float theta_o, float theta_i,
                              float phi, float out[3]);

/* The azimuthal scattering of each lobe averaged across half the fibre,
 * d'Eon 2011 eq. 3's N_p(phi) = 1/2 int A_p(h) D_p(phi - Phi_p(h)) dh with
 * Chiang 2016 eq. 10's logistic D_p and d'Eon eq. 12-14's A_p, over
 * h in [-1, 0] (half 0) and [0, 1] (half 1), each the mean over h by
 * SATF_FIBER_AZ_H midpoints in gamma_o = asin h: what a strand thinner than a
 * pixel shows of each side (the remainder: A_3 / (2 pi)). It depends on the
 * view's inclination only through |sin theta_o| (eta', the paths and Fresnel
 * are even in it), rows k of SATF_FIBER_AZ_ROWS at |sin theta_o| = k / (rows
 * - 1), and on the light's azimuth from the view's, columns j of
 * SATF_FIBER_AZ_COLS at phi = -pi + 2 pi j / cols (periodic). */
#define SATF_FIBER_AZ_ROWS 64
#define SATF_FIBER_AZ_COLS 256
#define SATF_FIBER_AZ_H 64
#define SATF_FIBER_AZ_LAYERS (2 * SATF_FIBER_LOBES) /* half * lobes + p */
/* Fills out[((layer * rows + k) * cols + j) * 3 + c], layer = half *
 * SATF_FIBER_LOBES + p (an RGB 2-D array texture of SATF_FIBER_AZ_LAYERS
 * layers), on `threads` threads (0: all). */
void satf_fiber_azimuthal_table(const satf_fiber *f, int threads, float *out);
/* Bilinear look-up of the table at sin theta_o and phi (any angle), as a
 * GPU's linear filter reads it: out[c] for layer `layer`. */
void satf_fiber_azimuthal_lookup(const float *table, int layer,
                                 float sin_theta_o, float phi, float out[3]);

/* The four lobes' M_p (d'Eon 2011 eq. 7) on an n x n grid of (sin
 * theta_i, sin theta_o), node (a, b) at sin theta_i = -1 + 2 a / (n - 1)
 * and sin theta_o = -1 + 2 b / (n - 1), into out[4 (b n + a) + p]: R, TT
 * and TRT with their tilts (satf_fiber_tilt) and variances, the remainder
 * untilted with variance v_rest (the fibre's own v[3], or what a caller
 * takes for light scattered more than once). n >= 2. */
#define SATF_FIBER_MP_NODES 256
void satf_fiber_mp_table(const satf_fiber *f, float v_rest, int n, float *out);

#ifdef __cplusplus
}
#endif

#endif
