/* dom_write.glsl - a fragment of hair (or a mesh) drawn into the deep
 * opacity map (Yuksel & Keyser 2008): its optical depth added into the
 * slab its depth falls in, the first three slabs one u_dom_slab deep
 * behind the texel's first hair (u_dom_depth, the depth pass's) and the
 * last taking all beyond; and its depth into the second target, blended
 * by GL_MAX into (-first hair's depth, last hair's depth), so that a
 * look-up (dom_behind.glsl) reads both in one fetch and spreads the last
 * slab's hair from three slabs to the last hair. The including fragment
 * shader declares u_dom_depth and u_dom_slab. */
layout(location = 0) out vec4 o_opacity;
layout(location = 1) out vec4 o_depths;
/* optical_depth spread evenly in depth from this fragment's depth to
 * z_other (the same: all in the slab the fragment falls in), each slab
 * taking its share. A cluster's outermost shell carries the alpha of its
 * whole radial column at (u, t) (dom_fs.glsl), hair that lies between the
 * shell and the cluster's axis: put at the shell, a light's ray that
 * enters a cluster through the edge of a neighbour whose envelope overlaps
 * it counted the neighbour's column at once (the imported ponytail,
 * front-lit: luminance 0.88 of Cycles' -> 0.91 spread to the axis). */
void dom_write_spread(float optical_depth, float z_other) {
  float d0 = texelFetch(u_dom_depth, ivec2(gl_FragCoord.xy), 0).r;
  float s = max(gl_FragCoord.z - d0, 0.0) / u_dom_slab;
  float s2 = max(z_other - d0, 0.0) / u_dom_slab;
  float lo = min(s, s2), hi = max(s, s2);
  vec4 o = vec4(0.0);
  if (hi - lo < 1e-3) {
    o[int(min(s, 3.0))] = optical_depth; /* adds along the ray */
  } else { /* slabs [0, 1), [1, 2), [2, 3) and [3, all beyond) */
    const vec4 from = vec4(0.0, 1.0, 2.0, 3.0), to = vec4(1.0, 2.0, 3.0, 1e30);
    o = optical_depth * (clamp(vec4(hi), from, to) - clamp(vec4(lo), from, to)) /
        (hi - lo);
  }
  o_opacity = o;
  o_depths = vec4(-gl_FragCoord.z, gl_FragCoord.z, 0.0, 0.0);
}
void dom_write(float optical_depth) {
  dom_write_spread(optical_depth, gl_FragCoord.z);
}
