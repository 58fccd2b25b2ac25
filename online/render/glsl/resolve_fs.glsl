#version 430 core
/* resolve_fs.glsl - SATF eq. 14: a pixel's fragments sorted far to near
 * and composited. The renderer defines SATF_MAX_FRAGMENTS. */
#define MAXF SATF_MAX_FRAGMENTS
layout(binding = 0, r32ui) uniform readonly uimage2D u_counts;
layout(binding = 1, rgba32ui) uniform readonly uimage2DArray u_frags;
uniform int u_slots;
out vec4 o_color;
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
  int n = min(int(imageLoad(u_counts, px).r), min(u_slots, MAXF));
  for (int k = 0; k < n; k++) f[k] = imageLoad(u_frags, ivec3(px, k));
  for (int a = 1; a < n; a++) {
    uvec4 x = f[a];
    int b = a - 1;
    while (b >= 0 && farther(x, f[b])) { f[b + 1] = f[b]; b--; }
    f[b + 1] = x;
  }
  /* SATF eq. 14 over every cluster, back to front */
  vec3 c = vec3(0.0); /* premultiplied, blended over the background and meshes */
  float transmit = 1.0;
  for (int a = 0; a < n; a++) {
    vec4 p = vec4(unpackHalf2x16(f[a].x), unpackHalf2x16(f[a].y));
    c = c * (1.0 - p.a) + p.rgb;
    transmit *= 1.0 - p.a;
  }
  o_color = vec4(c, 1.0 - transmit);
}
