/* map_fetch.glsl - the maps of a cluster: rows 2i and 2i+1 hold HSV i's
 * two boundary records (maps.h); mixing them by the position along the
 * HSV is SATF eq. 7. Included by the layer programs' fragment shaders. */
uniform sampler2DArray u_maps;
/* the instance's first layer in u_maps, which holds the maps of several
 * instances (cluster_vs.glsl, layer_vs.glsl) */
flat in int v_layer0;
uniform int u_st;
uniform int u_map_width;  /* texels around the cluster */
vec4 fetch_map(float u_turns, float t, int layer) {
  float ts = clamp(t, 0.0, 1.0) * float(u_st);
  int i = min(int(ts), u_st - 1);
  int x = min(int(fract(u_turns) * float(u_map_width)), u_map_width - 1);
  vec4 a = texelFetch(u_maps, ivec3(x, 2 * i, v_layer0 + layer), 0);
  vec4 b = texelFetch(u_maps, ivec3(x, 2 * i + 1, v_layer0 + layer), 0);
  return mix(a, b, ts - float(i));
}
/* SATF maps give reflectance and alpha (the --no-satf baseline has its
 * own shaders: baseline_fs.glsl) */
vec2 reflectance_alpha(vec4 m) { return m.rg; }
