#version 430 core
/* maps_sums_cs.glsl - the s-map sums of eq. 12 (maps.c:
 * satf_maps_shadow_sums) in the maps maps_kk_cs.glsl has just written:
 * channel 2 of layer k, the alpha of the layers m > k at the same texel.
 * One invocation per texel of an instance's layer (work group z: the
 * instance's entry), over its layers outer to inner. It adds the alphas as
 * the texture keeps them (halfs), as the CPU's maps do for the texels they
 * keep (cluster_cpu.c). The renderer defines MAPS_W. */
layout(local_size_x = 64) in;

layout(rgba16f, binding = 0) uniform image2DArray u_maps;

struct MapsInst {
  vec4 eye, light;
  ivec4 base, shell;
};
layout(std430, binding = 5) readonly buffer maps_insts { MapsInst g_inst[]; };

uniform int u_first;

void main() {
  MapsInst in_ = g_inst[u_first + int(gl_WorkGroupID.z)];
  int width = in_.shell.x * MAPS_W, rows = 2 * in_.shell.y;
  int t = int((gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) *
                  gl_WorkGroupSize.x + gl_LocalInvocationID.x);
  if (t >= width * rows)
    return;
  ivec3 at = ivec3(t % width, t / width, in_.base.w + in_.shell.z - 1);
  float sum = 0.0;
  for (; at.z >= in_.base.w; at.z--) {
    vec4 v = imageLoad(u_maps, at);
    imageStore(u_maps, at, vec4(v.x, v.y, sum, v.w));
    sum += v.y;
  }
}
