/* dom_lookup.glsl - deep opacity map (Yuksel & Keyser 2008): optical
 * depth of hair between a light and a point, from four slabs behind the
 * first hair. The including shader declares what dom_behind.glsl (included
 * here, with its texels' optical depths) needs; cluster_transmittance reads
 * the key light's map.
 *
 * Filtered by percentage-closer filtering (Reeves et al. 1987): the
 * transmittance is computed per texel, each with its own first-hair depth,
 * and those results are averaged with bilinear weights over 2 x 2 texels.
 * Filtering the depth itself (bilinear) would blend a near cluster's depth
 * with the cleared far depth at every cluster edge and draw the map's
 * texels as steps; filtering the result gives soft penumbrae instead. */
#include "dom_behind.glsl"
float dom_texel_transmittance(sampler2D dd, sampler2D od, float slab,
                              ivec2 c, float z) {
  return exp(-u_kcluster * dom_texel_depths(dd, od, slab, c, z).x);
}
/* The map of depths dd and slabs od (view vp, slabs `slab` deep) at a
 * point; bias: depth units subtracted from the point's depth (towards the
 * light) */
float dom_transmittance(sampler2D dd, sampler2D od, mat4 vp, float slab,
                       vec3 world, float bias) {
  vec4 p = vp * vec4(world, 1.0);
  vec3 q = p.xyz / p.w * 0.5 + 0.5;
  if (any(lessThan(q.xy, vec2(0.0))) || any(greaterThan(q.xy, vec2(1.0))))
    return 1.0;
  vec2 size = vec2(textureSize(dd, 0));
  vec2 x = q.xy * size - 0.5;
  ivec2 c = ivec2(floor(x)); /* the texel centre below and left */
  vec2 f = x - vec2(c);
  /* receiver-plane depth bias (Isidoro 2006): each tap compares the depth
   * the receiving surface has at that texel's centre, not the point's
   * own, or a surface sloped towards the light shadows itself in bands
   * (acne). The slope in depth per texel comes from the screen-space
   * derivatives, clamped where the surface is edge-on to the light. */
  vec3 qx = dFdx(vec3(x, q.z)), qy = dFdy(vec3(x, q.z));
  float det = qx.x * qy.y - qx.y * qy.x;
  vec2 slope = abs(det) > 1e-8
                   ? vec2(qy.y * qx.z - qx.y * qy.z, qx.x * qy.z - qy.x * qx.z) /
                         det
                   : vec2(0.0);
  slope = clamp(slope, -slab, slab);
  float sum = 0.0, wsum = 0.0;
  /* bilinear weights over the 2 x 2 texels around the point: continuous
   * as the point moves, and four look-ups (a 3 x 3 tent cost twice as
   * much on llvmpipe for little visible difference at 512 x 512) */
  for (int j = 0; j <= 1; j++)
    for (int i = 0; i <= 1; i++) {
      vec2 o = vec2(i, j) - f;
      float w = (i == 0 ? 1.0 - f.x : f.x) * (j == 0 ? 1.0 - f.y : f.y);
      float z = q.z - bias + dot(slope, o);
      sum += w * dom_texel_transmittance(dd, od, slab, c + ivec2(i, j), z);
      wsum += w;
    }
  return sum / wsum;
}
float cluster_transmittance(vec3 world, float bias) {
  return dom_transmittance(u_dom_depth, u_dom_opacity, u_light_viewproj,
                           u_dom_slab, world, bias);
}
float cluster_transmittance(vec3 world) {
  return cluster_transmittance(world, 0.0);
}
