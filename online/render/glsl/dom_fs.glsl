#version 430 core
/* dom_fs.glsl - the deep opacity map's slabs: each cluster's alpha added
 * into the slabs between its outermost shell and its axis. */
#ifndef PHYSICAL
#define PHYSICAL 0
#endif
#include "map_fetch.glsl"
in vec2 v_uv;
in float v_centre_z; /* the depth of the cluster's axis at v_uv's t */
uniform sampler2D u_dom_depth;
uniform float u_dom_slab;
#include "dom_write.glsl"
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
  dom_write_spread(a, v_centre_z); /* summed alpha ~ optical depth */
}
