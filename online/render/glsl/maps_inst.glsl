/* maps_inst.glsl - the instances a maps pass builds (maps_gpu.c:
 * gpu_inst), shared by the maps' compute shaders. Per instance built: eye
 * (xyz) and the curl in radians (w), key light (xyzw: w 0 direction, 1
 * position) in its frame; first
 * sector, first sector neighbours, first HSV neighbours, first texture
 * layer; su, st, layers, orientation_free. */
struct MapsInst {
  vec4 eye, light;
  ivec4 base, shell;
};
layout(std430, binding = 5) readonly buffer maps_insts { MapsInst g_inst[]; };

uniform int u_first; /* this dispatch's first entry of g_inst */

/* this invocation's index among the dispatch's work groups of 64, x by y
 * (maps_gpu.c: groups) */
int maps_invocation() {
  return int((gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) *
                 gl_WorkGroupSize.x + gl_LocalInvocationID.x);
}
