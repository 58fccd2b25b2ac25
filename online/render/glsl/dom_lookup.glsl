/* dom_lookup.glsl - deep opacity map (Yuksel & Keyser 2008): optical
 * depth of hair between the key light and a point, from four slabs behind
 * the first hair (filtered: the map is coarse, and its texels must not
 * show). The including shader declares u_light_viewproj, u_dom_depth,
 * u_dom_opacity, u_dom_slab and u_kcluster. */
float cluster_transmittance(vec3 world) {
  vec4 p = u_light_viewproj * vec4(world, 1.0);
  vec3 q = p.xyz / p.w * 0.5 + 0.5;
  if (any(lessThan(q.xy, vec2(0.0))) || any(greaterThan(q.xy, vec2(1.0))))
    return 1.0;
  float d0 = texture(u_dom_depth, q.xy).r;
  vec4 o = texture(u_dom_opacity, q.xy);
  float s = max(q.z - d0, 0.0) / u_dom_slab;
  float depth = o.x * clamp(s, 0.0, 1.0) + o.y * clamp(s - 1.0, 0.0, 1.0) +
                o.z * clamp(s - 2.0, 0.0, 1.0) + o.w * clamp(s - 3.0, 0.0, 1.0);
  return exp(-u_kcluster * depth);
}
