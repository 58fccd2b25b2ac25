#version 430 core
/* strand_dom_fs.glsl - the deep opacity map built from the strands
 * (strands.c; Yuksel & Keyser 2008, as dom_fs.glsl does for clusters):
 * with u_depth_only the first hair's depth (fragments that cover nothing
 * write none), then each strand fragment's coverage added into the slab
 * its depth falls in, the units of dom_fs.glsl (summed alpha ~ optical
 * depth). */
#include "strand_cover.glsl"
noperspective in float v_across;
noperspective in float v_width;
uniform sampler2D u_dom_depth;
uniform float u_dom_slab;
uniform int u_depth_only;
#include "dom_write.glsl"
void main() {
  float cover = strand_coverage(v_across, v_width);
#ifdef WHOLE_DEPTH
  /* the cluster path's opaque pre-pass (sparse.c): only the fragments a
   * strand covers whole, by strand_fs.glsl's test, write their depth */
  if (cover < 1.0 - 1.0 / 1024.0) discard;
  o_opacity = o_depths = vec4(0.0);
  return;
#endif
  if (cover <= 0.0) discard;
  if (u_depth_only != 0) {
    o_opacity = o_depths = vec4(0.0);
    return;
  }
  dom_write(cover);
}
