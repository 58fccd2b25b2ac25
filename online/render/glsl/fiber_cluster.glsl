/* fiber_cluster.glsl - the fibre model's uniforms and its tabulated
 * multiple scattering, shared by the cluster path's physical mode
 * (maps_fiber.h: cluster_vs.glsl, which evaluates it per vertex, and
 * shade_fs.glsl) and the strands' (strand_fs.glsl, per fragment). No
 * #version line: included. */
#include "fiber.glsl"
uniform float u_fiber_eta, u_fiber_s, u_fiber_alpha;
uniform vec4 u_fiber_v;
uniform vec3 u_fiber_sigma_a;
uniform sampler2D u_fiber_tables;
/* Multiple scattering between clusters (Zinke 2008, fiber.glsl): the key
 * light reaching a layer point after forward scattering through the hairs
 * in front of it. Its BCSDF (f_s^G + d_b f_back^G, with d_f) is a function
 * of the angles and, through the spread, of the depth. Our choice: one
 * value per vertex of the outer shell (cluster_vs.glsl), interpolated over
 * the fragments, at the spread of one hair (Zinke's max(n, 1) beta_f^2:
 * deeper points' wider spread is not added), for the fibre's middle
 * (h = 0); per layer point only the transmittance at that point's depth.
 * Per fragment it cost more than the rest of the physical shading, and
 * evaluated per vertex (fiber_dual_global) still 9 of anim_8's 71 ms, so
 * the vertex reads it from its table over the three angles
 * (satf_fiber_dual_global_table, filtered: within 2.5% of its peak up to
 * 66 degrees from the normal plane, test_fiber_dual). In the fibre frame:
 * x along the hair, y
 * the view's direction across it. */
uniform sampler3D u_fiber_global, u_fiber_back;
vec3 key_global(vec3 hair, vec3 v, vec3 l, out vec3 back) {
  vec3 y = v - dot(v, hair) * hair;
  if (dot(y, y) < 1e-8) y = abs(hair.x) < 0.9 ? cross(hair, vec3(1, 0, 0))
                                                : cross(hair, vec3(0, 1, 0));
  y = normalize(y);
  vec3 z = cross(hair, y);
  /* satf_fiber_global_coords */
  float to = fiber_asin(dot(v, hair)), ti = fiber_asin(dot(l, hair));
  float d = abs(fiber_atan2(dot(l, z), dot(l, y))) - 0.5 * FIBER_PI;
  float wh = max(0.5 * sqrt(u_fiber_v.y), 0.02), wp = 2.0 * u_fiber_s;
  vec3 at = vec3(
      0.5 + 0.5 * asinh(0.5 * (to + ti) / wh) / asinh(0.5 * FIBER_PI / wh),
      0.5 + (to - ti) / (2.0 * FIBER_PI),
      0.5 + 0.5 * asinh(d / wp) / asinh(0.5 * FIBER_PI / wp));
  back = texture(u_fiber_back, at).rgb;
  return texture(u_fiber_global, at).rgb;
}
