/* dom_behind.glsl - the hairs behind a point along a light, within the
 * deep opacity map's four slabs (dom_lookup.glsl's map): the map's whole
 * optical depth at the point's texels minus the depth up to one slab past
 * the point, bilinear over 2 x 2 texels. No derivatives, so a compute
 * shader may include it. The including shader declares u_light_viewproj,
 * u_dom_depth, u_dom_opacity, u_dom_slab and u_kcluster (the key light's
 * map: cluster_hairs_behind), and where it defines DOM_FILL u_fill_depth,
 * u_fill_opacity, u_fill_viewproj and u_fill_slab (the fill light's:
 * fill_hairs_behind). */
/* a texel's optical depth in front of depth z (x) and in all (y); dd: the
 * map's (-first, last) hair's depths (dom_write.glsl), od: its slabs */
vec2 dom_texel_depths(sampler2D dd, sampler2D od, float slab, ivec2 c,
                      float z) {
  c = clamp(c, ivec2(0), textureSize(dd, 0) - 1);
  vec2 nf = texelFetch(dd, c, 0).rg; /* -first hair's depth, last hair's */
  float d0 = -nf.x;
  vec4 o = texelFetch(od, c, 0);
  float s = max(z - d0, 0.0) / slab;
  /* the share of each slab in front of s: the last from three slabs to
   * the last hair, at least one slab deep. Read as one slab deep (the
   * paper's fixed layers), a point four slabs in counted all the hair
   * beyond three in front of it, what lies behind the point included: on
   * a hollow volume (curls over a scalp without a head mesh, the key light
   * through both sides) the far side shadowed the near side, and the
   * generated curls came to 0.58 of Cycles' luminance (320x240, 16 spp),
   * 0.79 spread so. A point past the last hair counts all of it. */
  float last = (s - 3.0) / max((nf.y - d0) / slab - 3.0, 1.0);
  float at = dot(o, clamp(vec4(s, s - 1.0, s - 2.0, last), 0.0, 1.0));
  return vec2(at, o.x + o.y + o.z + o.w);
}
float dom_texel_behind(sampler2D dd, sampler2D od, float slab, ivec2 c,
                       float z) {
  vec2 d = dom_texel_depths(dd, od, slab, c, z);
  return max(d.y - d.x, 0.0);
}
float dom_hairs_behind(sampler2D dd, sampler2D od, mat4 vp, float slab,
                       vec3 world) {
  vec4 p = vp * vec4(world, 1.0);
  vec3 q = p.xyz / p.w * 0.5 + 0.5;
  /* from one slab further from the light: the point's own strand lies in
   * the slab it falls in and is not behind it (a lone strand has none) */
  q.z += slab;
  if (any(lessThan(q.xy, vec2(0.0))) || any(greaterThan(q.xy, vec2(1.0))))
    return 0.0;
  vec2 x = q.xy * vec2(textureSize(dd, 0)) - 0.5;
  ivec2 c = ivec2(floor(x));
  vec2 f = x - vec2(c);
  float sum = mix(mix(dom_texel_behind(dd, od, slab, c, q.z),
                      dom_texel_behind(dd, od, slab, c + ivec2(1, 0), q.z),
                      f.x),
                  mix(dom_texel_behind(dd, od, slab, c + ivec2(0, 1), q.z),
                      dom_texel_behind(dd, od, slab, c + ivec2(1, 1), q.z),
                      f.x),
                  f.y);
  return u_kcluster * sum;
}
float cluster_hairs_behind(vec3 world) {
  return dom_hairs_behind(u_dom_depth, u_dom_opacity, u_light_viewproj,
                          u_dom_slab, world);
}
/* The transmittance e^-n at a point without screen derivatives (a
 * compute shader's, dom_lookup.glsl's without its receiver-plane bias):
 * per texel, bilinear over 2 x 2 texels; bias: depth units towards the
 * light */
float dom_point_transmittance(sampler2D dd, sampler2D od, mat4 vp,
                              float slab, vec3 world, float bias) {
  vec4 p = vp * vec4(world, 1.0);
  vec3 q = p.xyz / p.w * 0.5 + 0.5;
  q.z -= bias;
  if (any(lessThan(q.xy, vec2(0.0))) || any(greaterThan(q.xy, vec2(1.0))))
    return 1.0;
  vec2 x = q.xy * vec2(textureSize(dd, 0)) - 0.5;
  ivec2 c = ivec2(floor(x));
  vec2 f = x - vec2(c);
  float t[4];
  for (int i = 0; i < 4; i++)
    t[i] = exp(-u_kcluster *
               dom_texel_depths(dd, od, slab, c + ivec2(i & 1, i >> 1), q.z).x);
  return mix(mix(t[0], t[1], f.x), mix(t[2], t[3], f.x), f.y);
}
#ifdef DOM_FILL
float fill_point_transmittance(vec3 world, float bias) {
  return dom_point_transmittance(u_fill_depth, u_fill_opacity,
                                 u_fill_viewproj, u_fill_slab, world, bias);
}
float fill_hairs_behind(vec3 world) {
  return dom_hairs_behind(u_fill_depth, u_fill_opacity, u_fill_viewproj,
                          u_fill_slab, world);
}
#endif
