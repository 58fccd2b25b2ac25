/* map_fetch.glsl - the maps of a cluster: rows 2i and 2i+1 hold HSV i's
 * two boundary records (maps.h); mixing them by the position along the
 * HSV is SATF eq. 7. The maps hold reflectance (radiance) per unit alpha
 * (maps.c: lay_row), so eq. 7 mixes it weighted by each record's alpha,
 * as the records' own opacity-weighted reflectance (eq. 5) mixes: a
 * boundary where no strand is yet (a cluster's first slice above its
 * roots, its last below the tips) thins the HSV out but does not darken
 * what strands the HSV holds (mixed as stored, a cluster's root row ran
 * from black: docs/method.md, "Reflectance scale"). Included by the layer
 * programs' fragment shaders, after PHYSICAL is defined. */
#if PHYSICAL
/* a texel holds the key light's quad and the fill's (maps_fiber.h) as 8
 * halfs in 4 words, low half first: one fetch reads both, where two
 * RGBA16F slices cost the shading pass a second fetch per point (anim_8:
 * L 82 -> 71 ms, bench_shading) */
uniform usampler2DArray u_maps;
#else
uniform sampler2DArray u_maps;
#endif
/* the instance's first layer in u_maps, which holds the maps of several
 * instances (cluster_vs.glsl, layer_vs.glsl) */
flat in int v_layer0;
uniform int u_st;
uniform int u_map_width;  /* texels around the cluster */
/* the texels of (u, t) in layer `layer`: x and row 2i; the HSV's mix */
ivec3 map_texel(float u_turns, float t, int layer, out float f) {
  float ts = clamp(t, 0.0, 1.0) * float(u_st);
  int i = min(int(ts), u_st - 1);
  int x = min(int(fract(u_turns) * float(u_map_width)), u_map_width - 1);
  f = ts - float(i);
  return ivec3(x, 2 * i, v_layer0 + layer);
}
#if PHYSICAL
vec4 unpack_key(uvec4 w) {
  return vec4(unpackHalf2x16(w.x), unpackHalf2x16(w.y));
}
vec4 unpack_fill(uvec4 w) {
  return vec4(unpackHalf2x16(w.z), unpackHalf2x16(w.w));
}
/* the key light's quad (radiance, alpha) and the fill's (radiance, s-map
 * sum) */
void fetch_maps(float u_turns, float t, int layer, out vec4 key,
                out vec4 fill) {
  float f;
  ivec3 p = map_texel(u_turns, t, layer, f);
  uvec4 a = texelFetch(u_maps, p, 0);
  uvec4 b = texelFetch(u_maps, p + ivec3(0, 1, 0), 0);
  vec4 ka = unpack_key(a), kb = unpack_key(b);
  vec4 fa = unpack_fill(a), fb = unpack_fill(b);
  /* both lights' radiance is per unit of the key quad's alpha */
  float wa = (1.0 - f) * ka.a, wb = f * kb.a, al = wa + wb;
  float inv = al > 0.0 ? 1.0 / al : 0.0;
  key = vec4((wa * ka.rgb + wb * kb.rgb) * inv, al);
  fill = vec4((wa * fa.rgb + wb * fb.rgb) * inv, mix(fa.a, fb.a, f));
}
#else
vec4 fetch_map(float u_turns, float t, int layer) {
  float f;
  ivec3 p = map_texel(u_turns, t, layer, f);
  vec4 a = texelFetch(u_maps, p, 0);
  vec4 b = texelFetch(u_maps, p + ivec3(0, 1, 0), 0);
  vec4 m = mix(a, b, f);
  /* reflectance (r) per unit alpha (g), mixed weighted by alpha */
  m.r = m.g > 0.0 ? mix(a.r * a.g, b.r * b.g, f) / m.g : 0.0;
  return m;
}
/* SATF maps give reflectance and alpha (the --no-satf baseline has its
 * own shaders: baseline_fs.glsl) */
vec2 reflectance_alpha(vec4 m) { return m.rg; }
#endif
