/* shaders.c - GLSL of the online renderer. Formulas cite SATF (paper 001)
 * and Scheuermann (paper 002).
 *
 * How a cluster is drawn. Only the front faces of its outermost shell are
 * rasterised; each fragment follows its eye ray through the nested shells
 * analytically and composites, front to back, the layer points P(u,v),k it
 * meets: the front half of every shell from the outside in, then the back
 * half (seen through the transparent core) from the inside out. This is
 * SATF eq. 13-14 evaluated at exactly the points the paper's per-layer
 * blending would blend, but one fragment per pixel and cluster does the work
 * of 2L, which on a CPU rasteriser is several times faster than drawing
 * every layer mesh. The local geometry is the generalized cylinder's: at the
 * fragment's t the shells are the ellipses v (A cos, B sin) (eq. 1), which in
 * coordinates scaled by 1/A, 1/B are circles of radius v. */
#include "shaders.h"

#define GLSL_VERSION "#version 430 core\n"

/* SATF eq. 9-11: Kajiya-Kay diffuse and the two shifted highlights. */
#define LIGHTING                                                               \
  "float sin_between(vec3 a, vec3 b) {\n"                                      \
  "  float c = dot(a, b);\n"                                                   \
  "  return sqrt(max(0.0, 1.0 - c * c));\n"                                    \
  "}\n"                                                                        \
  "/* SATF eq. 9: Kajiya-Kay diffuse */\n"                                     \
  "float kk_diffuse(vec3 t, vec3 l) { return sin_between(t, l); }\n"           \
  "/* SATF eq. 10-11 with the tangent shifted along the cluster normal\n"      \
  " * (paper 002: T' = normalize(T + s N)). The extracted eq. 10 reads\n"      \
  " * (t.l)(t.v) + sin sin; with v pointing to the viewer that peaks at\n"     \
  " * retro-reflection, so we use the mirror form sin sin - (t.l)(t.v)\n"      \
  " * (Kajiya-Kay measure the eye vector towards the surface). */\n"           \
  "float kk_specular_cosine(vec3 t, vec3 l, vec3 v) {\n"                       \
  "  return sin_between(t, l) * sin_between(t, v) - dot(t, l) * dot(t, v);\n"  \
  "}\n"                                                                        \
  "float kk_specular(vec3 t, vec3 l, vec3 v, float e) {\n"                     \
  "  return pow(max(kk_specular_cosine(t, l, v), 0.0), e);\n"                  \
  "}\n"                                                                        \
  "vec3 shifted(vec3 t, vec3 n, float s) { return normalize(t + s * n); }\n"

const char *const satf_glsl_lighting = LIGHTING;

/* Deep opacity map (Yuksel & Keyser 2008): optical depth of hair between
 * the key light and a point, from four slabs behind the first hair
 * (filtered: the map is coarse, and its texels must not show). */
#define DOM_LOOKUP                                                             \
  "float cluster_transmittance(vec3 world) {\n"                                \
  "  vec4 p = u_light_viewproj * vec4(world, 1.0);\n"                          \
  "  vec3 q = p.xyz / p.w * 0.5 + 0.5;\n"                                      \
  "  if (any(lessThan(q.xy, vec2(0.0))) || any(greaterThan(q.xy, "             \
  "vec2(1.0))))\n"                                                             \
  "    return 1.0;\n"                                                          \
  "  float d0 = texture(u_dom_depth, q.xy).r;\n"                               \
  "  vec4 o = texture(u_dom_opacity, q.xy);\n"                                 \
  "  float s = max(q.z - d0, 0.0) / u_dom_slab;\n"                             \
  "  float depth = o.x * clamp(s, 0.0, 1.0) + o.y * clamp(s - 1.0, 0.0, 1.0) " \
  "+\n"                                                                        \
  "                o.z * clamp(s - 2.0, 0.0, 1.0) + o.w * clamp(s - 3.0, "     \
  "0.0, 1.0);\n"                                                               \
  "  return exp(-u_kcluster * depth);\n"                                       \
  "}\n"

/* Maps of a cluster: rows 2i and 2i+1 hold HSV i's two boundary records
 * (maps.h); mixing them by the position along the HSV is SATF eq. 7. */
#define MAP_FETCH                                                              \
  "uniform sampler2DArray u_maps;\n"                                           \
  "uniform int u_st;\n"                                                        \
  "uniform int u_satf;\n"                                                      \
  "uniform float u_plain_opacity;\n"                                           \
  "uniform int u_map_width;  /* texels around the cluster */\n"                \
  "vec4 fetch_map(float u_turns, float t, int layer) {\n"                      \
  "  float ts = clamp(t, 0.0, 1.0) * float(u_st);\n"                           \
  "  int i = min(int(ts), u_st - 1);\n"                                        \
  "  int x = min(int(fract(u_turns) * float(u_map_width)), u_map_width - "     \
  "1);\n"                                                                      \
  "  vec4 a = texelFetch(u_maps, ivec3(x, 2 * i, layer), 0);\n"                \
  "  vec4 b = texelFetch(u_maps, ivec3(x, 2 * i + 1, layer), 0);\n"            \
  "  return mix(a, b, ts - float(i));\n"                                       \
  "}\n"                                                                        \
  "/* SATF maps give reflectance and alpha; the plain mode (paper 002) has\n"  \
  " * unit reflectance and an opacity from the mean density alone */\n"        \
  "vec2 reflectance_alpha(vec4 m) {\n"                                         \
  "  if (u_satf != 0) return m.rg;\n"                                          \
  "  return vec2(1.0, 1.0 - exp(-u_plain_opacity * m.a));\n"                   \
  "}\n"

/* Outermost shell only, for the light's passes. */
const char *const satf_glsl_layer_vs =
    GLSL_VERSION "layout(location = 0) in vec3 a_pos;\n"
                 "layout(location = 3) in vec2 a_uv;\n"
                 "uniform mat4 u_model;\n"
                 "uniform mat4 u_viewproj;\n"
                 "out vec2 v_uv;\n"
                 "void main() {\n"
                 "  v_uv = a_uv;\n"
                 "  gl_Position = u_viewproj * (u_model * vec4(a_pos, 1.0));\n"
                 "}\n";

/* The outermost shell with the cluster's local frame at each vertex: the
 * trajectory point C(t), the normal-plane frame n1, n2, the trajectory's
 * unit tangent and |dT/dt|, and A, B, theta, all in the prototype's frame. */
const char *const satf_glsl_cluster_vs = GLSL_VERSION
    "layout(location = 0) in vec3 a_pos;\n"
    "layout(location = 2) in vec3 a_tangent;\n"
    "layout(location = 3) in vec2 a_uv;\n"
    "layout(location = 4) in vec3 a_centre;\n"
    "layout(location = 5) in vec3 a_n1;\n"
    "layout(location = 6) in vec3 a_n2;\n"
    "layout(location = 7) in vec4 a_shape;  /* A, B, theta, |dT/dt| */\n"
    "layout(location = 8) in vec3 a_axis;   /* unit tangent of T */\n"
    "uniform mat4 u_model;\n"
    "uniform mat4 u_viewproj;\n"
    "out vec3 v_local;\n"
    "out vec3 v_world;\n"
    "out vec3 v_hair;\n"
    "out float v_t;\n"
    "out vec3 v_centre;\n"
    "out vec3 v_n1;\n"
    "out vec3 v_n2;\n"
    "out vec4 v_shape;\n"
    "out vec3 v_axis;\n"
    "void main() {\n"
    "  vec4 w = u_model * vec4(a_pos, 1.0);\n"
    "  v_local = a_pos;\n"
    "  v_world = w.xyz;\n"
    "  v_hair = a_tangent;\n"
    "  v_t = a_uv.y;\n"
    "  v_centre = a_centre;\n"
    "  v_n1 = a_n1;\n"
    "  v_n2 = a_n2;\n"
    "  v_shape = a_shape;\n"
    "  v_axis = a_axis;\n"
    "  gl_Position = u_viewproj * w;\n"
    "}\n";

/* Compiled twice: with EXACT defined, each fragment (one cluster's
 * composite along the pixel's ray) goes to per-pixel arrays resolved by
 * satf_glsl_resolve_fs; without, it is written for fixed-function "over"
 * blending of clusters drawn far to near. */
const char *const satf_glsl_shade_fs = GLSL_VERSION
    "#ifndef EXACT\n"
    "#define EXACT 1\n"
    "#endif\n"
    "#ifndef NLIGHTS /* the renderer defines the scene's light count */\n"
    "#define NLIGHTS 1\n"
    "#endif\n" MAP_FETCH LIGHTING "in vec3 v_local;\n"
    "in vec3 v_world;\n"
    "in vec3 v_hair;\n"
    "in float v_t;\n"
    "in vec3 v_centre;\n"
    "in vec3 v_n1;\n"
    "in vec3 v_n2;\n"
    "in vec4 v_shape;\n"
    "in vec3 v_axis;\n"
    "uniform vec3 u_eye_local;       /* the eye in the prototype's frame */\n"
    "uniform int u_nlights;\n"
    "uniform vec4 u_light_local[4];  /* xyz, w: 0 direction to light, 1 "
    "position */\n"
    "uniform vec3 u_light_color[4];\n"
    "uniform int u_layers;\n"
    "uniform float u_core;\n"
    "uniform float u_kdif, u_kspe1, u_kspe2, u_exp1, u_exp2, u_shift1, "
    "u_shift2;\n"
    "uniform vec3 u_fdif, u_fspe1, u_fspe2;\n"
    "uniform float u_kshadow, u_noise;\n"
    "uniform int u_secondary, u_self_shadow, u_cluster_shadow;\n"
    "uniform sampler2D u_dom_depth;\n"
    "uniform sampler2D u_dom_opacity;\n"
    "uniform mat4 u_light_viewproj;\n"
    "uniform float u_dom_slab;\n"
    "uniform float u_kcluster;\n"
    "uniform int u_aov;  /* 0 beauty, 1 diffuse, 2 specI, 3 specII, 4 shadow, "
    "5 alpha */\n"
    "#if EXACT\n"
    "uniform int u_slots;\n"
    "layout(binding = 0, r32ui) uniform coherent uimage2D u_counts;\n"
    "layout(binding = 1, rgba32ui) uniform writeonly uimage2DArray u_frags;\n"
    "#else\n"
    "out vec4 o_color;\n"
    "#endif\n"
    "/* paper 002's noise texture, as an integer hash: one value per\n"
    " * strand-wide column, varying slowly along t */\n"
    "float hash(uint x) {\n"
    "  x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu;\n"
    "  x ^= x >> 16;\n"
    "  return float(x >> 8) * (1.0 / 16777216.0);\n"
    "}\n"
    "float strand_noise(float u_turns, float t) {\n"
    "  uint col = uint(fract(u_turns) * 1024.0);\n"
    "  float y = clamp(t, 0.0, 1.0) * 6.0, row = floor(y);\n"
    "  uint r = uint(row);\n"
    "  return mix(hash(col * 8u + r), hash(col * 8u + r + 1u), y - row);\n"
    "}\n"
    "/* atan2 in turns ([-1/2, 1/2]), a 5th-order minimax fit good to 1e-5\n"
    " * turns: a map texel is 1e-3 turns wide, and the exact atan costs\n"
    " * several times more on a CPU rasteriser */\n"
    "float atan2_turns(float y, float x) {\n"
    "  float ax = abs(x), ay = abs(y);\n"
    "  float a = min(ax, ay) / max(max(ax, ay), 1e-30);\n"
    "  float s = a * a;\n"
    "  float r = ((-0.0464964749 * s + 0.15931422) * s - 0.327622764) * s * a "
    "+ a;\n"
    "  if (ay > ax) r = 1.57079637 - r;\n"
    "  if (x < 0.0) r = 3.14159274 - r;\n"
    "  if (y < 0.0) r = -r;\n"
    "  return r * 0.159154943;\n"
    "}\n"
    "/* Deep opacity map (Yuksel & Keyser 2008): optical depth of hair "
    "between\n"
    " * the key light and this point, from four slabs behind the first hair. "
    "*/\n" DOM_LOOKUP
    "/* SATF eq. 8-11 for one side of the cluster: diffuse, primary and\n"
    " * secondary highlight (the latter without its noise factor) */\n"
    "void lighting(vec3 t, vec3 n, vec3 v, float dom, out vec3 dif,\n"
    "              out vec3 s1, out vec3 s2) {\n"
    "  dif = s1 = s2 = vec3(0.0);\n"
    "  vec3 t1 = shifted(t, n, u_shift1), t2 = shifted(t, n, -u_shift2);\n"
    "  for (int k = 0; k < NLIGHTS; k++) {\n"
    "    vec3 dl = u_light_local[k].xyz - u_light_local[k].w * v_local;\n"
    "    vec3 l = normalize(dl);\n"
    "    /* point lights fall off as 1 / d^2 (samples/README.md) */\n"
    "    float fall = u_light_local[k].w > 0.0 ? 1.0 / max(dot(dl, dl), 1e-6) "
    ": 1.0;\n"
    "    vec3 c = u_light_color[k] * fall * (k == 0 ? dom : 1.0);\n"
    "    dif += c * u_kdif * kk_diffuse(t, l) * u_fdif;\n"
    "    s1 += c * u_kspe1 * kk_specular(t1, l, v, u_exp1) * u_fspe1;\n"
    "    if (u_secondary != 0)\n"
    "      s2 += c * u_kspe2 * kk_specular(t2, l, v, u_exp2) * u_fspe2;\n"
    "  }\n"
    "}\n"
    "vec3 select_aov(vec3 dif, vec3 s1, vec3 s2) {\n"
    "  if (u_aov == 1) return dif;\n"
    "  if (u_aov == 2) return s1;\n"
    "  if (u_aov == 3) return s2;\n"
    "  return dif + s1 + s2;\n"
    "}\n"
    "void main() {\n"
    "  float A = v_shape.x, B = v_shape.y, theta = v_shape.z;\n"
    "  vec3 n1 = normalize(v_n1), n2 = normalize(v_n2), axis = "
    "normalize(v_axis);\n"
    "  vec3 d = normalize(v_local - u_eye_local);\n"
    "  vec3 q = v_local - v_centre;\n"
    "  /* the ray in the normal plane, scaled so the shells are circles */\n"
    "  vec2 P = vec2(dot(q, n1) / A, dot(q, n2) / B);\n"
    "  vec2 D = vec2(dot(d, n1) / A, dot(d, n2) / B);\n"
    "  float dt_ds = dot(d, axis) / max(v_shape.w, 1e-6);\n"
    "  float a = max(dot(D, D), 1e-12), b = dot(P, D), c0 = dot(P, P);\n"
    "  /* outer normals where the ray enters and leaves the cluster */\n"
    "  float s_out = (-b + sqrt(max(b * b - a * (c0 - 1.0), 0.0))) / a;\n"
    "  vec2 Pout = P + s_out * D;\n"
    "  vec3 n_front = normalize(P.x / A * n1 + P.y / B * n2);\n"
    "  vec3 n_back = normalize(Pout.x / A * n1 + Pout.y / B * n2);\n"
    "  vec3 hair = normalize(v_hair), v = -d;\n"
    "  float dom = u_cluster_shadow != 0 ? cluster_transmittance(v_world) : "
    "1.0;\n"
    "  vec3 df, s1f, s2f, db, s1b, s2b;\n"
    "  lighting(hair, n_front, v, dom, df, s1f, s2f);\n"
    "  vec3 col = vec3(0.0);\n"
    "  float transmit = 1.0, noise = -1.0;\n"
    "  int inner = 0;  /* innermost shell the ray meets */\n"
    "  /* SATF eq. 14 front to back: the front halves, outer to inner, then\n"
    "   * the back halves, inner to outer */\n"
    "  for (int pass = 0; pass < 2; pass++) {\n"
    "    /* the back side is lit only if the ray gets that far */\n"
    "    if (pass == 1) lighting(hair, n_back, v, dom, db, s1b, s2b);\n"
    "    for (int j = 0; j < u_layers; j++) {\n"
    "      int k = pass == 0 ? u_layers - 1 - j : inner + j;\n"
    "      if (k >= u_layers) break;\n"
    "      float r = u_core + (1.0 - u_core) * float(k + 1) / "
    "float(u_layers);\n"
    "      float disc = b * b - a * (c0 - r * r);\n"
    "      if (disc <= 0.0) { inner = k + 1; break; }\n"
    "      float s = (-b + (pass == 0 ? -1.0 : 1.0) * sqrt(disc)) / a;\n"
    "      vec2 X = P + s * D;\n"
    "      float u_turns = atan2_turns(X.y, X.x) - theta * 0.159154943;\n"
    "      float t = v_t + s * dt_ds;\n"
    "      vec4 m = fetch_map(u_turns, t, k);\n"
    "      vec2 ra = reflectance_alpha(m);\n"
    "      if (ra.y < 1.0 / 1024.0) continue;\n"
    "      /* SATF eq. 12: exponential s-map from the outer layers' alpha */\n"
    "      float tau = u_self_shadow != 0 ? exp(-u_kshadow * m.b) : 1.0;\n"
    "      vec3 y;\n"
    "      if (u_aov == 4) y = vec3(tau * dom);\n"
    "      else if (u_aov == 5) y = vec3(1.0);\n"
    "      else {\n"
    "        if (noise < 0.0) /* once per ray: the strands it meets first */\n"
    "          noise = mix(1.0, 2.0 * strand_noise(u_turns, t), u_noise);\n"
    "        vec3 L = pass == 0 ? select_aov(df, s1f, s2f * noise)\n"
    "                           : select_aov(db, s1b, s2b * noise);\n"
    "        y = L * ra.x * tau;  /* SATF eq. 13 */\n"
    "      }\n"
    "      col += transmit * ra.y * y;\n"
    "      transmit *= 1.0 - ra.y;\n"
    "      /* what lies behind can change the pixel by less than 1/512 */\n"
    "      if (transmit < 1.0 / 512.0) break;\n"
    "    }\n"
    "    if (transmit < 1.0 / 512.0) break;\n"
    "  }\n"
    "  float alpha = 1.0 - transmit;\n"
    "#if EXACT\n"
    "  if (alpha < 1.0 / 1024.0) return;\n"
    "  /* per-pixel fragment arrays: a slot from the pixel's own counter */\n"
    "  ivec2 px = ivec2(gl_FragCoord.xy);\n"
    "  int slot = int(imageAtomicAdd(u_counts, px, 1u));\n"
    "  if (slot >= u_slots) return;\n"
    "  imageStore(u_frags, ivec3(px, slot),\n"
    "             uvec4(packHalf2x16(col.rg), packHalf2x16(vec2(col.b, "
    "alpha)),\n"
    "                   floatBitsToUint(gl_FragCoord.z), 0u));\n"
    "#else\n"
    "  if (alpha < 1.0 / 1024.0) discard;\n"
    "  o_color = vec4(col, alpha);\n"
    "#endif\n"
    "}\n";

const char *const satf_glsl_depth_fs =
    GLSL_VERSION MAP_FETCH "in vec2 v_uv;\n"
                           "void main() {}\n";

const char *const satf_glsl_dom_fs = GLSL_VERSION MAP_FETCH
    "in vec2 v_uv;\n"
    "uniform sampler2D u_dom_depth;\n"
    "uniform float u_dom_slab;\n"
    "uniform int u_layers;\n"
    "out vec4 o_opacity;\n"
    "void main() {\n"
    "  /* drawn for the outermost shell only: the innermost layer's s-map sum\n"
    "   * plus its own alpha is the alpha of every layer at this (u, t) */\n"
    "  vec4 m = fetch_map(v_uv.x, v_uv.y, 0);\n"
    "  float a = u_satf != 0 ? m.b + m.g : reflectance_alpha(m).y * "
    "float(u_layers);\n"
    "  float d0 = texelFetch(u_dom_depth, ivec2(gl_FragCoord.xy), 0).r;\n"
    "  float s = max(gl_FragCoord.z - d0, 0.0) / u_dom_slab;\n"
    "  int slab = int(min(s, 3.0));\n"
    "  vec4 o = vec4(0.0);\n"
    "  o[slab] = a; /* summed alpha ~ optical depth, adds along the ray */\n"
    "  o_opacity = o;\n"
    "}\n";

const char *const satf_glsl_fullscreen_vs = GLSL_VERSION
    "out vec2 v_uv;\n"
    "void main() {\n"
    "  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));\n"
    "  v_uv = p;\n"
    "  gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);\n"
    "}\n";

#define STR2(x) #x
#define STR(x) STR2(x)

const char *const satf_glsl_resolve_fs = GLSL_VERSION "#define MAXF " STR(
    SATF_MAX_FRAGMENTS) "\n"
                        "layout(binding = 0, r32ui) uniform readonly uimage2D "
                        "u_counts;\n"
                        "layout(binding = 1, rgba32ui) uniform readonly "
                        "uimage2DArray u_frags;\n"
                        "uniform int u_slots;\n"

                        "out vec4 o_color;\n"
                        "/* far before near; equal depths ordered by colour "
                        "bits so the result\n"
                        " * does not depend on the order fragments arrived in "
                        "*/\n"
                        "bool farther(uvec4 a, uvec4 b) {\n"
                        "  float da = uintBitsToFloat(a.z), db = "
                        "uintBitsToFloat(b.z);\n"
                        "  if (da != db) return da > db;\n"
                        "  if (a.x != b.x) return a.x > b.x;\n"
                        "  return a.y > b.y;\n"
                        "}\n"
                        "void main() {\n"
                        "  uvec4 f[MAXF];\n"
                        "  ivec2 px = ivec2(gl_FragCoord.xy);\n"
                        "  int n = min(int(imageLoad(u_counts, px).r), "
                        "min(u_slots, MAXF));\n"
                        "  for (int k = 0; k < n; k++) f[k] = "
                        "imageLoad(u_frags, ivec3(px, k));\n"
                        "  for (int a = 1; a < n; a++) {\n"
                        "    uvec4 x = f[a];\n"
                        "    int b = a - 1;\n"
                        "    while (b >= 0 && farther(x, f[b])) { f[b + 1] = "
                        "f[b]; b--; }\n"
                        "    f[b + 1] = x;\n"
                        "  }\n"
                        "  /* SATF eq. 14 over every cluster, back to front "
                        "*/\n"
                        "  vec3 c = vec3(0.0); /* premultiplied, blended "
                        "over the background and meshes */\n"
                        "  float transmit = 1.0;\n"
                        "  for (int a = 0; a < n; a++) {\n"
                        "    vec4 p = vec4(unpackHalf2x16(f[a].x), "
                        "unpackHalf2x16(f[a].y));\n"
                        "    c = c * (1.0 - p.a) + p.rgb;\n"
                        "    transmit *= 1.0 - p.a;\n"
                        "  }\n"
                        "  o_color = vec4(c, 1.0 - transmit);\n"
                        "}\n";

const char *const satf_glsl_display_fs = GLSL_VERSION
    "uniform sampler2D u_image;\n"
    "in vec2 v_uv;\n"
    "out vec4 o_color;\n"
    "float srgb(float x) {\n"
    "  x = clamp(x, 0.0, 1.0);\n"
    "  return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;\n"
    "}\n"
    "void main() {\n"
    "  vec3 c = texture(u_image, v_uv).rgb;\n"
    "  o_color = vec4(srgb(c.r), srgb(c.g), srgb(c.b), 1.0);\n"
    "}\n";

/* Opaque meshes (a head): Lambert shading under the scene's lights, the key
 * light attenuated by the hair's deep opacity map. */
const char *const satf_glsl_mesh_vs =
    GLSL_VERSION "layout(location = 0) in vec3 a_pos;\n"
                 "layout(location = 1) in vec3 a_normal;\n"
                 "uniform mat4 u_model;\n"
                 "uniform mat3 u_normal_matrix;\n"
                 "uniform mat4 u_viewproj;\n"
                 "out vec3 v_world;\n"
                 "out vec3 v_normal;\n"
                 "void main() {\n"
                 "  vec4 w = u_model * vec4(a_pos, 1.0);\n"
                 "  v_world = w.xyz;\n"
                 "  v_normal = u_normal_matrix * a_normal;\n"
                 "  gl_Position = u_viewproj * w;\n"
                 "}\n";

const char *const satf_glsl_mesh_fs = GLSL_VERSION
    "in vec3 v_world;\n"
    "in vec3 v_normal;\n"
    "uniform vec3 u_albedo;\n"
    "uniform vec3 u_eye;\n"
    "uniform int u_nlights;\n"
    "uniform vec4 u_light_vec[4];\n"
    "uniform vec3 u_light_color[4];\n"
    "uniform int u_cluster_shadow;\n"
    "uniform sampler2D u_dom_depth;\n"
    "uniform sampler2D u_dom_opacity;\n"
    "uniform mat4 u_light_viewproj;\n"
    "uniform float u_dom_slab;\n"
    "uniform float u_kcluster;\n"
    "uniform int u_aov;\n"
    "out vec4 o_color;\n" DOM_LOOKUP "void main() {\n"
    "  if (u_aov != 0) { o_color = vec4(0.0, 0.0, 0.0, 1.0); return; }\n"
    "  vec3 n = normalize(v_normal);\n"
    "  if (dot(n, u_eye - v_world) < 0.0) n = -n; /* either side */\n"
    "  vec3 c = 0.12 * u_albedo; /* sky fill, so unlit sides read */\n"
    "  for (int k = 0; k < u_nlights; k++) {\n"
    "    vec3 dl = u_light_vec[k].xyz - u_light_vec[k].w * v_world;\n"
    "    float fall = u_light_vec[k].w > 0.0 ? 1.0 / max(dot(dl, dl), 1e-6) : "
    "1.0;\n"
    "    float sh = k == 0 && u_cluster_shadow != 0 ?\n"
    "               cluster_transmittance(v_world + 0.02 * n) : 1.0;\n"
    "    c += u_light_color[k] * fall * sh * max(dot(n, normalize(dl)), 0.0) "
    "*\n"
    "         u_albedo;\n"
    "  }\n"
    "  o_color = vec4(c, 1.0);\n"
    "}\n";

const char *const satf_glsl_empty_fs = GLSL_VERSION "void main() {}\n";

/* Meshes in the deep opacity map: opaque, so a large optical depth in the
 * slab where the light meets them. */
const char *const satf_glsl_dom_mesh_fs = GLSL_VERSION
    "uniform sampler2D u_dom_depth;\n"
    "uniform float u_dom_slab;\n"
    "out vec4 o_opacity;\n"
    "void main() {\n"
    "  float d0 = texelFetch(u_dom_depth, ivec2(gl_FragCoord.xy), 0).r;\n"
    "  float s = max(gl_FragCoord.z - d0, 0.0) / u_dom_slab;\n"
    "  vec4 o = vec4(0.0);\n"
    "  o[int(min(s, 3.0))] = 8.0;\n"
    "  o_opacity = o;\n"
    "}\n";
