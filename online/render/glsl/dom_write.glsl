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
void dom_write(float optical_depth) {
  float d0 = texelFetch(u_dom_depth, ivec2(gl_FragCoord.xy), 0).r;
  float s = max(gl_FragCoord.z - d0, 0.0) / u_dom_slab;
  vec4 o = vec4(0.0);
  o[int(min(s, 3.0))] = optical_depth; /* adds along the ray */
  o_opacity = o;
  o_depths = vec4(-gl_FragCoord.z, gl_FragCoord.z, 0.0, 0.0);
}
