#version 430 core
/* resolve_fs.glsl - SATF eq. 14: a pixel's fragments sorted far to near
 * and composited; with DEPTH (SATF_AOV_DEPTH) the depth where they, front
 * to back, first reach half coverage. The renderer defines
 * SATF_MAX_FRAGMENTS. */
#ifndef DEPTH
#define DEPTH 0
#endif
/* 1: the plain pass's fragments past the slots are in the pool (a second
 * program: the pool's loop in the one every frame draws made hair_7a's
 * shading 15-25% slower on llvmpipe, taken or not) */
#ifndef POOL
#define POOL 0
#endif
#define MAXF SATF_MAX_FRAGMENTS
layout(binding = 0, r32ui) uniform readonly uimage2D u_counts;
layout(binding = 1, rgba32ui) uniform readonly uimage2DArray u_frags;
uniform int u_slots;
out vec4 o_color;
#if POOL
/* the plain pass's fragments past the slots (glsl/list_write.glsl): the
 * nearest passes were not drawn */
layout(binding = 3, r32ui) uniform readonly uimage2D u_heads;
layout(std430, binding = 7) readonly buffer satf_pool {
  uint g_pool_count, g_pool_capacity, g_pool_pad0, g_pool_pad1;
  uvec4 g_pool[];
};
#endif
#if DEPTH
#include "depth_encode.glsl"
uniform mat4 u_inv_viewproj; /* the sample's, jitter and all */
uniform vec2 u_size;         /* the frame in pixels */
#endif
/* far before near; equal depths ordered by colour bits so the result
 * does not depend on the order fragments arrived in */
bool farther(uvec4 a, uvec4 b) {
  float da = uintBitsToFloat(a.z), db = uintBitsToFloat(b.z);
  if (da != db) return da > db;
  if (a.x != b.x) return a.x > b.x;
  return a.y > b.y;
}
void main() {
  uvec4 f[MAXF];
  ivec2 px = ivec2(gl_FragCoord.xy);
  int total = int(imageLoad(u_counts, px).r);
#if POOL
  /* the arrays' slots and the pool's chain: the MAXF nearest of both, as
   * arrays of MAXF slots would keep (lists.h: pool_slots) */
  int keep = MAXF, n = min(total, min(u_slots, MAXF));
#else
  int keep = min(u_slots, MAXF), n = min(total, keep);
#endif
  for (int k = 0; k < n; k++) f[k] = imageLoad(u_frags, ivec3(px, k));
  for (int a = 1; a < n; a++) {
    uvec4 x = f[a];
    int b = a - 1;
    while (b >= 0 && farther(x, f[b])) { f[b + 1] = f[b]; b--; }
    f[b + 1] = x;
  }
#if POOL
  /* the pixel's fragments in the pool: each nearer than the farthest kept
   * takes its place, so the `keep` nearest of all remain, whatever order
   * they arrived in (the nearest passes' result) */
  if (total > n) {
    for (uint i = imageLoad(u_heads, px).r; i != 0u;) {
      uvec4 x = g_pool[i - 1u];
      i = x.w;
      x.w = 0u;
      int b;
      if (n < keep) { /* room: insert */
        b = n - 1;
        while (b >= 0 && farther(x, f[b])) { f[b + 1] = f[b]; b--; }
        f[b + 1] = x;
        n++;
      } else if (farther(f[0], x)) { /* the farthest out, x in */
        b = 0;
        while (b + 1 < n && farther(f[b + 1], x)) { f[b] = f[b + 1]; b++; }
        f[b] = x;
      }
    }
  }
#endif
#if DEPTH
  /* Half coverage: the median of where rays through the pixel stop, so
   * the depth a path tracer's first hit gives most often (Blender's Z
   * takes one ray's first hit); the nearest fragment would give thin
   * wisps in front the depth of the whole pixel, a mean a depth between
   * hair and what lies behind, where nothing is. Fewer than half covered:
   * the meshes' depth, or the background, stays. */
  float transmit = 1.0;
  for (int a = n - 1; a >= 0; a--) {
    transmit *= 1.0 - unpackHalf2x16(f[a].y).y;
    if (transmit > 0.5) continue;
    vec3 ndc = vec3(gl_FragCoord.xy / u_size, uintBitsToFloat(f[a].z));
    vec4 w = u_inv_viewproj * vec4(2.0 * ndc - 1.0, 1.0);
    o_color = depth_encode(depth_of(w.xyz / w.w));
    return;
  }
  discard;
#else
  /* SATF eq. 14 over every cluster, back to front */
  vec3 c = vec3(0.0); /* premultiplied, blended over the background and meshes */
  float transmit = 1.0;
  for (int a = 0; a < n; a++) {
    vec4 p = vec4(unpackHalf2x16(f[a].x), unpackHalf2x16(f[a].y));
    c = c * (1.0 - p.a) + p.rgb;
    transmit *= 1.0 - p.a;
  }
  o_color = vec4(c, 1.0 - transmit);
#endif
}
