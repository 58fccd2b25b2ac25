#version 430 core
/* baseline_fs.glsl - the hair pixel shader of Scheuermann 2004 (paper 002),
 * SATF's Fig. 4(a) baseline: nothing here comes from the HRIR database.
 * The hair texture (baseline.c) holds per texel r: base brightness, g: the
 * tangent shift, b: the secondary highlight's noise, a: strand alpha.
 *
 * Compiled three times (BASE_PASS):
 *   0 the full pixel shader, premultiplied for "over" blending;
 *   1 alpha test only (paper 002's first pass, "a very simple pixel shader
 *     that only returns the hair's alpha channel"; also the deep opacity
 *     map's first-hair depth);
 *   2 the deep opacity map's slabs: each patch's alpha added into the slab
 *     its depth falls in (as dom_fs.glsl does for the SATF clusters);
 *   3 the depth AOV's: each patch's alpha and depth into the per-pixel
 *     fragment arrays (depth.c sorts them).
 * The renderer defines SATF_MAX_LIGHTS and NLIGHTS. */
#ifndef BASE_PASS
#define BASE_PASS 0
#endif
#ifndef NLIGHTS
#define NLIGHTS 1
#endif
in vec3 v_world;
in vec3 v_normal;
in vec3 v_tangent;
in vec2 v_uv;
in float v_ao;
uniform sampler2D u_hair;
#if BASE_PASS == 1
uniform float u_alpha_ref; /* the alpha test's reference */
void main() {
  if (texture(u_hair, v_uv).a < u_alpha_ref) discard;
}
#elif BASE_PASS == 2
uniform sampler2D u_dom_depth;
uniform float u_dom_slab;
#include "dom_write.glsl"
void main() {
  dom_write(texture(u_hair, v_uv).a); /* summed alpha ~ optical depth */
}
#elif BASE_PASS == 3
#include "list_write.glsl"
void main() {
  float a = texture(u_hair, v_uv).a;
  if (a >= 1.0 / 512.0) list_write(vec3(0.0), a);
}
#else
#include "lighting.glsl"
#include "baseline_lighting.glsl"
uniform vec3 u_eye;
uniform vec4 u_light_vec[SATF_MAX_LIGHTS]; /* xyz, w: 0 direction, 1 position */
uniform vec3 u_light_color[SATF_MAX_LIGHTS];
uniform float u_kdif, u_kspe1, u_kspe2, u_exp1, u_exp2, u_shift1, u_shift2;
uniform vec3 u_fdif, u_fspe1, u_fspe2;
uniform float u_noise;
uniform float u_shift_range; /* the shift texture's span */
uniform float u_base_scale;  /* decodes the base brightness */
uniform int u_secondary, u_ao, u_cluster_shadow;
uniform int u_aov; /* 0 beauty, 1 diffuse, 2 specI, 3 specII, 4 shadow, 5 alpha */
uniform sampler2D u_dom_depth;
uniform sampler2D u_dom_opacity;
uniform mat4 u_light_viewproj;
uniform float u_dom_slab;
uniform float u_kcluster;
#include "dom_lookup.glsl"
out vec4 o_color;
/* paper 002, "Early-Z Culling": the first pass primes depth "to avoid
 * using alpha-testing in the subsequent passes", whose fragments can then
 * be culled before shading: no discard here (a transparent texel blends
 * as nothing) */
layout(early_fragment_tests) in;
void main() {
  vec4 h = texture(u_hair, v_uv);
  /* between strands (what it drops changes a pixel by < 1/512): nothing
   * to light; returns, not discards */
  if (h.a < 1.0 / 512.0) { o_color = vec4(0.0); return; }
  /* the patch normal as the vertices carry it, on both faces: paper 002's
   * shader model 2.0 pixel shaders could not tell the faces apart */
  vec3 n = normalize(v_normal), t = normalize(v_tangent);
  vec3 v = normalize(u_eye - v_world);
  /* paper 002: T' = normalize(T + s N), s looked up in a texture and
   * added to each highlight's own shift (primary towards the tip,
   * secondary towards the root, as SATF eq. 10-11 place them) */
  float s = (h.g - 0.5) * u_shift_range;
  vec3 t1 = shifted(t, n, u_shift1 + s), t2 = shifted(t, n, -u_shift2 + s);
  float mask = scheuermann_noise_mask(h.b, u_noise);
  float dom = u_cluster_shadow != 0 ? cluster_transmittance(v_world) : 1.0;
  vec3 dif = vec3(0.0), s1 = vec3(0.0), s2 = vec3(0.0);
  for (int k = 0; k < NLIGHTS; k++) {
    vec3 dl = u_light_vec[k].xyz - u_light_vec[k].w * v_world;
    vec3 l = normalize(dl);
    /* point lights fall off as 1 / d^2 (samples/README.md) */
    float fall = u_light_vec[k].w > 0.0 ? 1.0 / max(dot(dl, dl), 1e-6) : 1.0;
    vec3 c = u_light_color[k] * fall * (k == 0 ? dom : 1.0);
    dif += c * u_kdif * scheuermann_diffuse(n, l) * u_fdif;
    s1 += c * u_kspe1 * kk_specular(t1, l, v, u_exp1) * u_fspe1;
    if (u_secondary != 0)
      s2 += c * u_kspe2 * kk_specular(t2, l, v, u_exp2) * u_fspe2 * mask;
  }
  /* paper 002: "we add the diffuse and specular terms and modulate the
   * sum by the base texture and the ambient occlusion term" */
  float ao = u_ao != 0 ? v_ao : 1.0;
  float base = h.r * u_base_scale;
  vec3 y;
  if (u_aov == 1) y = dif * base * ao;
  else if (u_aov == 2) y = s1 * base * ao;
  else if (u_aov == 3) y = s2 * base * ao;
  else if (u_aov == 4) y = vec3(ao * dom);
  else if (u_aov == 5) y = vec3(1.0);
  else y = (dif + s1 + s2) * base * ao;
  o_color = vec4(y * h.a, h.a); /* premultiplied */
}
#endif
