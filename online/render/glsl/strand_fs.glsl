#version 430 core
/* strand_fs.glsl - the strand reference path's shading: each strand
 * fragment lit as the cluster path lights hair (glsl/shade_fs.glsl): SATF
 * eq. 9-11 (Kajiya-Kay diffuse and the two shifted highlights of
 * lighting.glsl) with the scene's material and lights, the key light
 * attenuated by the deep opacity map (here built from the strands
 * themselves, strands.c), the secondary highlight's noise per strand.
 * The strand is opaque where it covers: alpha is its coverage of the
 * pixel (strand_cover.glsl), written premultiplied. Drawn twice
 * (strands.c): first the fragments a strand covers whole, depth-tested
 * and written, so overlapping wide strands hide each other pixel by pixel;
 * then the partly covered ones (edges, strands thinner than a pixel),
 * tested against that depth and blended "over" with the segments drawn
 * far to near. The renderer defines SATF_MAX_LIGHTS.
 *
 * Compiled with PHYSICAL 1 for the physical material: each fragment is a
 * fibre of the d'Eon/Chiang model (fiber.glsl) lit by every light's
 * irradiance (a directional light's intensity, as a Cycles sun's
 * strength; point lights over d^2) with Zinke's dual scattering: the key
 * light's deep opacity map counts the hairs in the way (summed coverage),
 * which gives the direct and the forward-scattered parts, and the local
 * back-scattering and global BCSDF come from the tables
 * (fiber_cluster.glsl: key_global, for the fibre's middle and the spread
 * of one hair; evaluated per fragment they took five sixths of the fibre
 * model's cost). The rest of the light, which needs no shadow, is
 * strand_light_cs.glsl's per point (strand_fiber.glsl), averaged over
 * each half of the fibre's offsets h and weighed by the pixel's share of
 * each; only strands wider than a few pixels are sampled at
 * the offsets each pixel covers (the ribbon faces the eye, so h is the
 * across-ribbon coordinate itself). AOVs there: 1 all but R and TRT (TT,
 * the remainder, multiple scattering), 2 R, 3 TRT.
 *
 * Compiled with LIST for sparse clusters drawn as strands in the cluster
 * path (sparse.c): each fragment goes, whole or partly covered, into the
 * per-pixel arrays (list_write.glsl) beside the clusters' fragments. */
#ifndef LIST
#define LIST 0
#endif
/* 0 Kajiya-Kay (SATF eq. 9-11), 1 the fibre model (the physical material) */
#ifndef PHYSICAL
#define PHYSICAL 0
#endif
#include "lighting.glsl"
#include "strand_cover.glsl"
#include "fiber_cluster.glsl"
in vec3 v_world;
in vec3 v_tangent;
in float v_t;
flat in uint v_strand;
noperspective in float v_across;
noperspective in float v_width;
uniform vec3 u_eye;
uniform int u_nlights;
uniform vec4 u_light_vec[SATF_MAX_LIGHTS]; /* world; w: 0 direction, 1 position */
uniform vec3 u_light_color[SATF_MAX_LIGHTS];
uniform float u_kdif, u_kspe1, u_kspe2, u_exp1, u_exp2, u_shift1, u_shift2;
uniform vec3 u_fdif, u_fspe1, u_fspe2;
uniform float u_noise;
uniform int u_secondary, u_cluster_shadow, u_fill_shadow;
uniform sampler2D u_fill_depth, u_fill_opacity;
uniform mat4 u_fill_viewproj;
uniform float u_fill_slab;
#define DOM_FILL 1
uniform sampler2D u_dom_depth;
uniform sampler2D u_dom_opacity;
uniform mat4 u_light_viewproj;
uniform float u_dom_slab;
uniform float u_kcluster;
uniform int u_aov; /* 0 beauty, 1 diffuse, 2 specI, 3 specII, 4 shadow, 5 alpha */
uniform int u_whole; /* 1: only whole coverage, 0: only partial, -1: all */
#if LIST
#include "list_write.glsl"
#else
out vec4 o_color;
#endif
/* the fragment's colour (premultiplied) and coverage */
void emit(vec3 col, float alpha) {
#if LIST
  list_write(col, alpha);
#else
  o_color = vec4(col, alpha);
#endif
}
#include "dom_lookup.glsl"
/* shade_fs.glsl's noise hash; here one column per strand, varying slowly
 * along the strand's t as there along the cluster's */
float hash(uint x) {
  x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu;
  x ^= x >> 16;
  return float(x >> 8) * (1.0 / 16777216.0);
}
float strand_noise(uint strand, float t) {
  float y = clamp(t, 0.0, 1.0) * 6.0, row = floor(y);
  uint r = uint(row);
  return mix(hash(strand * 8u + r), hash(strand * 8u + r + 1u), y - row);
}
#if PHYSICAL
/* The fibre model's light: strand_light_cs.glsl's per point, over each
 * half of the fibre, interpolated along the strand (strand_vs.glsl). A strand wider than STRAND_EXACT_WIDTH pixels shows
 * its pixels a part of the fibre each, so there the offsets h a pixel
 * covers ([d - 1/2, d + 1/2] of the ribbon's [-w/2, w/2]) are sampled per
 * fragment, at three points (one where the strand is wide). ribbons.c
 * defines it only in frames that have such strands: llvmpipe runs a
 * branch's code even where no fragment takes it, and this one's presence
 * alone made the pass twice as slow. */
in vec3 v_key_lo, v_key_hi, v_rest_lo, v_rest_hi, v_global, v_af;
/* the lobes' M_p from their table (satf_fiber_mp_table): per fragment
 * they were eight Bessel series a fragment of a wide strand */
uniform sampler2D u_fiber_mp;
#define STRAND_FIBER_MP_TABLE 1
const int STRAND_FIBER_MAX_H = 3;
#include "strand_fiber.glsl"
StrandLight strand_light(vec3 t, vec3 v) {
  float half_w = max(0.5 * v_width, 1e-6);
  float lo = max(v_across - 0.5, -half_w) / half_w,
        hi = min(v_across + 0.5, half_w) / half_w;
#ifdef STRAND_EXACT_WIDTH
  if (v_width > STRAND_EXACT_WIDTH) {
    int ns = hi - lo < 0.25 ? 1 : 3;
    StrandLight a, b;
    strand_fiber(t, v, v_world, lo, hi, ns, u_aov, a, b);
    float wb = float(ns - ns / 2) / float(ns); /* b's share of the samples */
    return StrandLight(mix(a.key, b.key, wb), b.global, b.af,
                       mix(a.rest, b.rest, wb), mix(a.fill, b.fill, wb),
                       b.fill_global, b.fill_af);
  }
#endif
  /* the share of the covered offsets [lo, hi] on the fibre's h > 0 half */
  float neg = max(min(hi, 0.0) - lo, 0.0), pos = max(hi - max(lo, 0.0), 0.0);
  float w = neg + pos > 0.0 ? pos / (neg + pos) : 0.5;
  /* the fill's light is in the rest, already shadowed */
  return StrandLight(mix(v_key_lo, v_key_hi, w), v_global, v_af,
                     mix(v_rest_lo, v_rest_hi, w), vec3(0.0), vec3(0.0),
                     vec3(0.0));
}
#endif

void main() {
  float cover = strand_coverage(v_across, v_width);
  if (cover < 1.0 / 1024.0) discard;
  /* whole: the same test in both passes, so each fragment is drawn once */
  bool whole = cover >= 1.0 - 1.0 / 1024.0;
  if (u_whole >= 0 && whole != (u_whole != 0)) discard;
  if (whole) cover = 1.0;
#if LIST
  /* the nearest-kept passes' first (cluster_gpu_lists): only the depth key of a
   * fragment that would be stored, which its coverage alone decides */
  if (u_list_mode == 1) {
    list_write(vec3(0.0), cover);
    return;
  }
#endif
  /* a hairpin's tip has no direction: a zero tangent lights as one
   * across every light (sin 1), never as NaN */
  vec3 t = v_tangent / max(length(v_tangent), 1e-30);
  vec3 v = normalize(u_eye - v_world);
  /* the highlight shift's normal (SATF eq. 10-11): the ribbon's, facing
   * the eye, as in the cluster path (lighting.glsl) */
  vec3 n = facing_normal(t, v);
  vec3 t1 = shifted(t, n, u_shift1), t2 = shifted(t, n, -u_shift2);
  /* the physical mode looks the map up one slab nearer the light: the
   * point's own strand sits in the slab the look-up interpolates into, so
   * without it each strand shadows itself by up to one hair, e^-1 of its
   * direct light (the ponytail front-lit: luminance against Cycles 0.71
   * at no bias, 0.82 at half a slab, 0.86 at one) */
  float dom = u_cluster_shadow != 0
                  ? cluster_transmittance(v_world,
                                          PHYSICAL != 0 ? u_dom_slab : 0.0)
                  : 1.0;
#if PHYSICAL
  /* the fill light's map: at the fragment where strand_light samples the
   * fibre here (wide strands), else in the rest already (per point) */
  float fill_dom = 1.0;
#ifdef STRAND_EXACT_WIDTH
  if (u_fill_shadow != 0 && v_width > STRAND_EXACT_WIDTH)
    fill_dom = fill_point_transmittance(v_world, u_fill_slab);
#endif
  vec3 y = strand_fiber_radiance(strand_light(t, v), dom, fill_dom);
  if (u_aov == 1) y = max(y, vec3(0.0)); /* all but R and TRT */
  else if (u_aov == 4) y = vec3(dom);
  else if (u_aov == 5) y = vec3(1.0);
  emit(y * cover, cover);
#else
  vec3 dif = vec3(0.0), s1 = vec3(0.0), s2 = vec3(0.0);
  for (int k = 0; k < u_nlights; k++) {
    vec3 dl = u_light_vec[k].xyz - u_light_vec[k].w * v_world;
    vec3 l = normalize(dl);
    /* point lights fall off as 1 / d^2 (samples/README.md) */
    float fall = u_light_vec[k].w > 0.0 ? 1.0 / max(dot(dl, dl), 1e-6) : 1.0;
    vec3 c = u_light_color[k] * fall * (k == 0 ? dom : 1.0);
    dif += c * u_kdif * kk_diffuse(t, l) * u_fdif;     /* SATF eq. 9 */
    s1 += c * u_kspe1 * kk_specular(t1, l, v, u_exp1) * u_fspe1; /* eq. 10 */
    if (u_secondary != 0)                              /* eq. 11 */
      s2 += c * u_kspe2 * kk_specular(t2, l, v, u_exp2) * u_fspe2;
  }
  s2 *= mix(1.0, 2.0 * strand_noise(v_strand, v_t), u_noise);
  vec3 y;
  if (u_aov == 1) y = dif;
  else if (u_aov == 2) y = s1;
  else if (u_aov == 3) y = s2;
  else if (u_aov == 4) y = vec3(dom);
  else if (u_aov == 5) y = vec3(1.0);
  else y = dif + s1 + s2;
  emit(y * cover, cover);
#endif
}
