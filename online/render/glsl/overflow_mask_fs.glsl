#version 430 core
/* overflow_mask_fs.glsl - the depth the nearest passes test against
 * (lists.c, lists_mask_overflow): the frame's depth where the plain pass
 * overflowed a pixel's slots, 0 (nothing passes LEQUAL but the near
 * plane, which list_write.glsl's list_skip still turns away) everywhere
 * else, so that their early depth test skips the shading of every pixel
 * they leave as it was. (An overflowed pixel's nearest fragments all lie
 * in front of the meshes, as more than its slots passed their depth in
 * the plain pass; the frame's depth there only spares the passes the
 * fragments behind them.) */
layout(binding = 0, r32ui) uniform readonly uimage2D u_counts;
uniform sampler2D u_depth; /* the frame's: meshes, opaque strands */
uniform int u_slots;
void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  bool over = imageLoad(u_counts, px).r > uint(u_slots);
  gl_FragDepth = over ? texelFetch(u_depth, px, 0).r : 0.0;
}
