/* fiber_cluster.glsl - the fibre model's part of the cluster path's
 * physical mode (maps_fiber.h), shared by cluster_vs.glsl, which evaluates
 * it per vertex, and shade_fs.glsl. No #version line: included. */
#include "fiber.glsl"
uniform float u_fiber_eta, u_fiber_s, u_fiber_alpha;
uniform vec4 u_fiber_v;
uniform vec3 u_fiber_sigma_a;
uniform sampler2D u_fiber_tables;
/* Multiple scattering between clusters (Zinke 2008, fiber.glsl): the key
 * light reaching a layer point after forward scattering through the hairs
 * in front of it. Its BCSDF (f_s^G + d_b f_back^G, with d_f) is a function
 * of the angles and, through the spread, of the depth. Our choice: one
 * evaluation per vertex of the outer shell (cluster_vs.glsl), interpolated
 * over the fragments, at the spread of one hair (Zinke's max(n, 1) beta_f^2:
 * deeper points' wider spread is not added), for the fibre's middle
 * (h = 0); per layer point only the transmittance at that point's depth.
 * Per fragment it cost more than the rest of the physical shading
 * (README, "Physical shading"). In the fibre frame: x along the hair, y
 * the view's direction across it. */
vec3 key_global(vec3 hair, vec3 v, vec3 l, float n_rep, out vec3 back) {
  Fiber f = Fiber(u_fiber_eta, u_fiber_v, u_fiber_s, u_fiber_sigma_a,
                  u_fiber_alpha);
  vec3 y = v - dot(v, hair) * hair;
  if (dot(y, y) < 1e-8) y = abs(hair.x) < 0.9 ? cross(hair, vec3(1, 0, 0))
                                                : cross(hair, vec3(0, 1, 0));
  y = normalize(y);
  vec3 z = cross(hair, y);
  vec3 wo = vec3(dot(v, hair), dot(v, y), dot(v, z));
  vec3 wi = vec3(dot(l, hair), dot(l, y), dot(l, z));
  return fiber_dual_global(f, u_fiber_tables, fiber_geom(f, wo, 0.0), wi,
                           n_rep, back);
}
