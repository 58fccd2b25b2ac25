/* strand_fiber.glsl - the fibre model's light at a point of a strand
 * (d'Eon/Chiang, fiber.glsl, with Zinke's dual scattering), averaged over
 * the offsets h in [lo, hi] across the fibre, for every light; split into
 * the parts that do not depend on the deep opacity map's hair count n, so
 * that strand_light_cs.glsl evaluates it once per point (and frame) and
 * strand_fs.glsl multiplies in only its per-fragment shadow
 * (strand_fiber_radiance). No
 * #version line: included after fiber_cluster.glsl and dom_behind.glsl
 * (with DOM_FILL) by a shader that declares u_eye, u_nlights, u_light_vec,
 * u_light_color, u_cluster_shadow, u_fill_shadow and u_aov.
 *
 * Per light: d'Eon 2011 eq. 7's M_p depends on the two inclinations only,
 * not on h, so it is evaluated once per lobe (not once per lobe and offset),
 * and phi_i once; only Chiang 2016 eq. 10's N_p and the A_p of d'Eon
 * eq. 12-14 are taken at each h. */
/* the most offsets a caller asks for: the includer's STRAND_FIBER_MAX_H
 * (a GLSL constant), as few as it needs, since llvmpipe pays for the
 * array's size even where the code that fills it is skipped */

/* The radiance of every light at a point, as Zinke 2008's dual scattering
 * adds it up (fiber_dual_shade): L = e^-n key + T_f(n) global + rest, with
 * n the hairs between the key light and the point and
 * T_f(n) = e^-n(1 - a_f) - e^-n the forward-scattered transmittance
 * (eq. 5 over a Poisson count). key: the key light's direct BCSDF
 * f_s + d_b f_back (eq. 20) times its irradiance; global: its
 * forward-scattered BCSDF (eq. 23-25) times the irradiance; af: a_f at its
 * inclination; fill, fill_global, fill_af: the same of the lights after
 * the key where the fill light's map shadows them (u_fill_shadow; af at the
 * fill's inclination); rest: the other lights, unshadowed (n = 0: direct
 * only). */
struct StrandLight {
  vec3 key, global, af, rest, fill, fill_global, fill_af;
};

/* The direct BCSDF f_s + d_b f_back of the lobes' sum (R, TT, TRT, the
 * remainder), or its part of AOV aov (1 all but R and TRT, 2 R, 3 TRT) */
vec3 strand_fiber_direct(vec3 lobe[4], vec3 back, float d_b, int aov) {
  if (aov == 2 || aov == 3) return aov == 2 ? lobe[0] : lobe[2];
  vec3 d = lobe[1] + lobe[3] + d_b * back;
  return aov == 1 ? d : d + lobe[0] + lobe[2];
}

/* t: the strand's unit tangent, v: towards the eye, world: the point;
 * h_lo, h_hi: the offsets the light is averaged over ([-1, 1]: the whole
 * fibre), at ns <= STRAND_FIBER_MAX_H midpoints, the first ns / 2 of them
 * into a, the others into b (each their average; a's light is b's where
 * ns is 1). aov 1-3 give the parts of strand_fs.glsl's AOVs instead of the
 * beauty: 1 all but R and TRT, 2 R, 3 TRT (the lobes lit directly). */
void strand_fiber(vec3 t, vec3 v, vec3 world, float h_lo, float h_hi, int ns,
                  int aov, out StrandLight a, out StrandLight b) {
  Fiber f = Fiber(u_fiber_eta, u_fiber_v, u_fiber_s, u_fiber_sigma_a,
                  u_fiber_alpha);
  /* the fibre frame: x along the strand, z towards the eye, so h runs
   * along y = z x x, the ribbon's +side (strand_vs.glsl: the screen's
   * across is the eye's axis cross the strand) */
  vec3 z = v - dot(v, t) * t;
  float zl = length(z);
  z = zl > 1e-6 ? z / zl
                : (abs(t.x) < 0.9 ? normalize(cross(t, vec3(1, 0, 0)))
                                  : normalize(cross(t, vec3(0, 1, 0))));
  vec3 y = cross(z, t);
  vec3 wo = vec3(dot(v, t), 0.0, dot(v, z));
  FiberGeom g[STRAND_FIBER_MAX_H];
  for (int j = 0; j < ns; j++)
    g[j] = fiber_geom(f, wo,
                      clamp(mix(h_lo, h_hi, (float(j) + 0.5) / float(ns)),
                            -1.0, 1.0));
  /* theta_o tilted per lobe (fiber_tilt): the same at every h and light */
  vec2 o[4];
  for (int p = 0; p < 4; p++)
    o[p] = fiber_tilt(f.alpha, p, g[0].sin_o, g[0].cos_o);
  /* Zinke's density factor d_b (eq. 9) where the key light's deep opacity
   * map tells: the local back-scattering is light that went past the point
   * into the hair behind it and came back, so it scales with the hairs
   * there, 1 - e^-n of FIBER_DUAL_DENSITY for n hairs behind within the
   * map's slabs. A choice where Zinke takes one constant for a hair volume:
   * a lone strand has none behind it, and the constant made sparse hair
   * 19% brighter than Cycles and 6 degrees off in hue (Bangs_100 at
   * 640x480, 64 spp; 1.0x and 2.5 degrees on generated sparse strands with
   * it), while in dense hair most points keep most of it. Without the map
   * the constant. */
  float d_b = FIBER_DUAL_DENSITY, d_b_fill = FIBER_DUAL_DENSITY;
  if (u_cluster_shadow != 0)
    d_b *= 1.0 - exp(-cluster_hairs_behind(world));
  /* the lights after the key: the hairs behind along the fill light */
  if (u_fill_shadow != 0)
    d_b_fill *= 1.0 - exp(-fill_hairs_behind(world));
  else
    d_b_fill = d_b;
#ifdef STRAND_FIBER_TABLE
  int na = 1; /* both halves from the table */
#else
  int na = ns / 2;
#endif
  float inv_a = 1.0 / float(max(na, 1)), inv_b = 1.0 / float(ns - na);
  a = StrandLight(vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0),
                  vec3(0.0), vec3(0.0));
  b = a;
  for (int k = 0; k < u_nlights; k++) {
    vec3 dl = u_light_vec[k].xyz - u_light_vec[k].w * world;
    vec3 l = normalize(dl);
    float fall = u_light_vec[k].w > 0.0 ? 1.0 / max(dot(dl, dl), 1e-6) : 1.0;
    vec3 e = u_light_color[k] * fall;
    vec3 wi = vec3(dot(l, t), dot(l, y), dot(l, z));
    float sin_i = clamp(wi.x, -1.0, 1.0);
    float cos_i = sqrt(max(1.0 - sin_i * sin_i, 0.0));
    float mp[4];
#ifdef STRAND_FIBER_MP_TABLE
    /* the four lobes' M_p, tilts included (satf_fiber_mp_table: nodes at
     * sin = -1 + 2 k / (SATF_FIBER_MP_NODES - 1)) */
    vec4 m4 = texture(u_fiber_mp,
                      ((vec2(sin_i, g[0].sin_o) + 1.0) * 0.5 *
                           float(SATF_FIBER_MP_NODES - 1) + 0.5) /
                          float(SATF_FIBER_MP_NODES));
    for (int p = 0; p < 4; p++) mp[p] = m4[p];
#else
    for (int p = 0; p < 4; p++)
      mp[p] = fiber_mp(cos_i, o[p].y, sin_i, o[p].x, f.v[p]);
#endif
    float dphi = fiber_atan2(wi.z, wi.y) - g[0].phi_o;
    vec3 la[4] = vec3[4](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
    vec3 lb[4] = la;
#ifdef STRAND_FIBER_TABLE
    /* the two halves of the whole fibre from the lobes' azimuthal table
     * (satf_fiber_azimuthal_table: texel centres at phi = -pi + 2 pi j /
     * cols, |sin theta_o| = k / (rows - 1); periodic in phi) */
    vec2 uv = vec2((dphi + FIBER_PI) / (2.0 * FIBER_PI) +
                       0.5 / float(SATF_FIBER_AZ_COLS),
                   (abs(g[0].sin_o) * float(SATF_FIBER_AZ_ROWS - 1) + 0.5) /
                       float(SATF_FIBER_AZ_ROWS));
    for (int p = 0; p < 4; p++) {
      la[p] = mp[p] * texture(u_fiber_azimuthal, vec3(uv, float(p))).rgb;
      lb[p] = mp[p] * texture(u_fiber_azimuthal, vec3(uv, float(4 + p))).rgb;
    }
#else
    for (int j = 0; j < ns; j++)
      for (int p = 0; p < 4; p++) {
        float np = p < 3 ? fiber_np(dphi, p, f.s, g[j].gamma_o, g[j].gamma_t)
                         : 0.5 / FIBER_PI;
        vec3 x = np * vec3(g[j].ap[0][p], g[j].ap[1][p], g[j].ap[2][p]);
        if (j < na) la[p] += x;
        else lb[p] += x;
      }
    for (int p = 0; p < 4; p++) {
      la[p] *= mp[p] * inv_a;
      lb[p] *= mp[p] * inv_b;
    }
#endif
    vec3 back;
    vec3 global = aov == 2 || aov == 3 ? vec3(0.0) : key_global(t, v, l, back);
    if (aov == 2 || aov == 3) back = vec3(0.0);
    float dbk = k == 0 ? d_b : d_b_fill;
    vec3 da = strand_fiber_direct(na > 0 ? la : lb, back, dbk, aov);
    vec3 db = strand_fiber_direct(lb, back, dbk, aov);
    if (k == 0 && u_cluster_shadow != 0) {
      a.key = e * da;
      b.key = e * db;
      a.global = b.global = e * global;
      a.af = b.af = fiber_dual_field(u_fiber_tables, 0, fiber_asin(sin_i));
    } else if (k > 0 && u_fill_shadow != 0) {
      a.fill += e * da;
      b.fill += e * db;
      a.fill_global += e * global;
      b.fill_global = a.fill_global;
      if (k == 1)
        a.fill_af = b.fill_af =
            fiber_dual_field(u_fiber_tables, 0, fiber_asin(sin_i));
    } else {
      a.rest += e * da;
      b.rest += e * db;
    }
  }
}

/* Zinke's direct and forward-scattered light of one shadowed light for
 * its transmittance dom = e^-n from its deep opacity map (u_kcluster is 1:
 * n counts hairs) */
vec3 strand_fiber_dual(vec3 direct, vec3 global, vec3 af, float dom) {
  float n = max(-log(max(dom, 1e-30)), 0.0);
  return exp(-n) * direct +
         max(exp(-n * (1.0 - af)) - exp(-n), vec3(0.0)) * global;
}
/* L of StrandLight for the key and fill lights' transmittances */
vec3 strand_fiber_radiance(StrandLight s, float dom, float fill_dom) {
  return strand_fiber_dual(s.key, s.global, s.af, dom) +
         strand_fiber_dual(s.fill, s.fill_global, s.fill_af, fill_dom) +
         s.rest;
}
