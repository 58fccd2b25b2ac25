#version 430 core
/* maps_sums_cs.glsl - the s-map sums of eq. 12 (maps.c:
 * satf_maps_shadow_sums) in the maps maps_kk_cs.glsl (or, with PHYSICAL,
 * maps_fiber_cs.glsl) has just written: the alpha of the layers m > k at
 * the same texel, into channel 2 of layer k (the paper's mode) or the
 * eighth half of its texel (the physical mode, maps_fiber.h). One
 * invocation per texel of an instance's layer (work group z: the
 * instance's entry), over its layers outer to inner. It adds the alphas as
 * the texture keeps them (halfs), as the CPU's maps do for the texels they
 * keep (cluster_cpu.c). The renderer defines MAPS_W and PHYSICAL. */
layout(local_size_x = 64) in;

#if PHYSICAL
layout(rgba32ui, binding = 0) uniform uimage2DArray u_maps;
#else
layout(rgba16f, binding = 0) uniform image2DArray u_maps;
#endif

#include "maps_inst.glsl"

void main() {
  MapsInst in_ = g_inst[u_first + int(gl_WorkGroupID.z)];
  int width = in_.shell.x * MAPS_W, rows = 2 * in_.shell.y;
  int t = maps_invocation();
  if (t >= width * rows)
    return;
  ivec3 at = ivec3(t % width, t / width, in_.base.w + in_.shell.z - 1);
  float sum = 0.0;
  for (; at.z >= in_.base.w; at.z--) {
#if PHYSICAL
    /* the key quad's alpha is half 4, the sum half 8 (words 1 and 3) */
    uvec4 v = imageLoad(u_maps, at);
    imageStore(u_maps, at,
               uvec4(v.xyz, packHalf2x16(vec2(unpackHalf2x16(v.w).x, sum))));
    sum += unpackHalf2x16(v.y).y;
#else
    vec4 v = imageLoad(u_maps, at);
    imageStore(u_maps, at, vec4(v.x, v.y, sum, v.w));
    sum += v.y;
#endif
  }
}
