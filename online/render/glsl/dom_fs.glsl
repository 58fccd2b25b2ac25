#version 430 core
/* dom_fs.glsl - the deep opacity map's slabs: each cluster's alpha added
 * into the slab its depth falls in. */
#ifndef PHYSICAL
#define PHYSICAL 0
#endif
#include "map_fetch.glsl"
in vec2 v_uv;
uniform sampler2D u_dom_depth;
uniform float u_dom_slab;
out vec4 o_opacity;
void main() {
  /* drawn for the outermost shell only: the innermost layer's s-map sum
   * plus its own alpha is the alpha of every layer at this (u, t) */
#if PHYSICAL /* alpha and the s-map sum, key and fill (maps_fiber.h) */
  vec4 key, fill;
  fetch_maps(v_uv.x, v_uv.y, 0, key, fill);
  float a = key.a + fill.a;
#else
  vec4 m = fetch_map(v_uv.x, v_uv.y, 0);
  float a = m.b + m.g;
#endif
  float d0 = texelFetch(u_dom_depth, ivec2(gl_FragCoord.xy), 0).r;
  float s = max(gl_FragCoord.z - d0, 0.0) / u_dom_slab;
  int slab = int(min(s, 3.0));
  vec4 o = vec4(0.0);
  o[slab] = a; /* summed alpha ~ optical depth, adds along the ray */
  o_opacity = o;
}
