/* shaders.c - GLSL of the online renderer. Formulas cite SATF (paper 001)
 * and Scheuermann (paper 002). */
#include "online/shaders.h"

#define GLSL_VERSION "#version 430 core\n"

/* SATF eq. 9-11: Kajiya-Kay diffuse and the two shifted highlights. */
#define LIGHTING \
  "float sin_between(vec3 a, vec3 b) {\n" \
  "  float c = dot(a, b);\n" \
  "  return sqrt(max(0.0, 1.0 - c * c));\n" \
  "}\n" \
  "/* SATF eq. 9: Kajiya-Kay diffuse */\n" \
  "float kk_diffuse(vec3 t, vec3 l) { return sin_between(t, l); }\n" \
  "/* SATF eq. 10-11 with the tangent shifted along the cluster normal\n" \
  " * (paper 002: T' = normalize(T + s N)). The extracted eq. 10 reads\n" \
  " * (t.l)(t.v) + sin sin; with v pointing to the viewer that peaks at\n" \
  " * retro-reflection, so we use the mirror form sin sin - (t.l)(t.v)\n" \
  " * (Kajiya-Kay measure the eye vector towards the surface). */\n" \
  "float kk_specular_cosine(vec3 t, vec3 l, vec3 v) {\n" \
  "  return sin_between(t, l) * sin_between(t, v) - dot(t, l) * dot(t, v);\n" \
  "}\n" \
  "float kk_specular(vec3 t, vec3 l, vec3 v, float e) {\n" \
  "  return pow(max(kk_specular_cosine(t, l, v), 0.0), e);\n" \
  "}\n" \
  "vec3 shifted(vec3 t, vec3 n, float s) { return normalize(t + s * n); }\n" \


const char *const satf_glsl_lighting = LIGHTING;

/* Lighting (SATF eq. 9-11) is evaluated per vertex up to the highlight
 * exponent: the cosines vary smoothly over a shell, and interpolating them
 * before the pow keeps highlights sharp while costing a small fraction of
 * per-fragment evaluation on a CPU rasteriser. The key light's deep opacity
 * map is sampled per vertex too (shadows between clusters vary on the scale
 * of clusters). */
const char *const satf_glsl_layer_vs =
    GLSL_VERSION
    "layout(location = 0) in vec3 a_pos;\n"
    "layout(location = 1) in vec3 a_normal;\n"
    "layout(location = 2) in vec3 a_tangent;\n"
    "layout(location = 3) in vec2 a_uv;\n"
    "uniform mat4 u_model;\n"
    "uniform mat3 u_normal_matrix;\n"
    "uniform mat4 u_viewproj;\n"
    "uniform vec3 u_eye;\n"
    "uniform int u_nlights;\n"
    "uniform vec4 u_light_vec[4];   /* xyz, w: 0 direction to light, 1 position */\n"
    "uniform float u_shift1, u_shift2;\n"
    "uniform int u_cluster_shadow;\n"
    "uniform sampler2D u_dom_depth;\n"
    "uniform sampler2D u_dom_opacity;\n"
    "uniform mat4 u_light_viewproj;\n"
    "uniform float u_dom_slab;       /* slab depth in light depth units */\n"
    "uniform float u_kcluster;\n"
    "out vec3 v_world;\n"
    "out vec3 v_normal;\n"
    "out vec3 v_tangent;\n"
    "out vec2 v_uv;\n"
    "out vec4 v_diffuse;   /* per light: kk_diffuse */\n"
    "out vec4 v_spec1;     /* per light: primary highlight cosine */\n"
    "out vec4 v_spec2;     /* per light: secondary highlight cosine */\n"
    "out float v_dom;      /* key light transmittance between clusters */\n"
    LIGHTING
    "/* Deep opacity map (Yuksel & Keyser 2008): optical depth of hair between\n"
    " * the key light and this point, from four slabs behind the first hair. */\n"
    "float cluster_transmittance(vec3 world) {\n"
    "  vec4 p = u_light_viewproj * vec4(world, 1.0);\n"
    "  vec3 q = p.xyz / p.w * 0.5 + 0.5;\n"
    "  if (any(lessThan(q.xy, vec2(0.0))) || any(greaterThan(q.xy, vec2(1.0))))\n"
    "    return 1.0;\n"
    "  ivec2 tq = ivec2(q.xy * vec2(textureSize(u_dom_depth, 0)));\n"
    "  float d0 = texelFetch(u_dom_depth, tq, 0).r;\n"
    "  vec4 o = texelFetch(u_dom_opacity, tq, 0);\n"
    "  float s = max(q.z - d0, 0.0) / u_dom_slab;\n"
    "  float depth = o.x * clamp(s, 0.0, 1.0) + o.y * clamp(s - 1.0, 0.0, 1.0) +\n"
    "                o.z * clamp(s - 2.0, 0.0, 1.0) + o.w * clamp(s - 3.0, 0.0, 1.0);\n"
    "  return exp(-u_kcluster * depth);\n"
    "}\n"
    "void main() {\n"
    "  vec4 w = u_model * vec4(a_pos, 1.0);\n"
    "  v_world = w.xyz;\n"
    "  v_normal = u_normal_matrix * a_normal;\n"
    "  v_tangent = mat3(u_model) * a_tangent;\n"
    "  v_uv = a_uv;\n"
    "  gl_Position = u_viewproj * w;\n"
    "  vec3 t = normalize(v_tangent), n = normalize(v_normal);\n"
    "  vec3 v = normalize(u_eye - w.xyz);\n"
    "  vec3 t1 = shifted(t, n, u_shift1), t2 = shifted(t, n, -u_shift2);\n"
    "  v_diffuse = v_spec1 = v_spec2 = vec4(0.0);\n"
    "  for (int k = 0; k < u_nlights; k++) {\n"
    "    vec3 l = normalize(u_light_vec[k].xyz - u_light_vec[k].w * w.xyz);\n"
    "    v_diffuse[k] = kk_diffuse(t, l);\n"
    "    v_spec1[k] = kk_specular_cosine(t1, l, v);\n"
    "    v_spec2[k] = kk_specular_cosine(t2, l, v);\n"
    "  }\n"
    "  v_dom = u_cluster_shadow != 0 ? cluster_transmittance(w.xyz) : 1.0;\n"
    "}\n";

/* Shared by the shading and deep-opacity passes: fetching the maps. */
#define MAP_FETCH                                                              \
  "uniform sampler2DArray u_maps;\n"                                           \
  "uniform int u_layer;\n"                                                     \
  "uniform int u_st;\n"                                                        \
  "uniform int u_satf;\n"                                                      \
  "uniform float u_plain_opacity;\n"                                           \
  "in vec3 v_world;\n"                                                         \
  "in vec3 v_normal;\n"                                                        \
  "in vec3 v_tangent;\n"                                                       \
  "in vec2 v_uv;\n"                                                            \
  "/* rows 2i and 2i+1 hold HSV i's two boundary records: mixing them by\n"   \
  " * the position along the HSV is SATF eq. 7 */\n"                          \
  "vec4 fetch_layer(int layer) {\n"                                            \
  "  ivec3 size = textureSize(u_maps, 0);\n"                                   \
  "  float ts = clamp(v_uv.y, 0.0, 1.0) * float(u_st);\n"                      \
  "  int i = min(int(ts), u_st - 1);\n"                                        \
  "  int x = int(fract(v_uv.x) * float(size.x)) % size.x;\n"                   \
  "  /* two texel fetches and a mix: cheaper than filtering on a CPU\n"        \
  "   * rasteriser, and exactly eq. 7 along t */\n"                           \
  "  vec4 a = texelFetch(u_maps, ivec3(x, 2 * i, layer), 0);\n"                \
  "  vec4 b = texelFetch(u_maps, ivec3(x, 2 * i + 1, layer), 0);\n"            \
  "  return mix(a, b, ts - float(i));\n"                                       \
  "}\n"                                                                        \
  "vec4 fetch_map() { return fetch_layer(u_layer); }\n"                        \
  "/* SATF maps give reflectance and alpha; the plain mode (paper 002) has\n"  \
  " * unit reflectance and an opacity from the mean density alone */\n"       \
  "vec2 reflectance_alpha(vec4 m) {\n"                                         \
  "  if (u_satf != 0) return m.rg;\n"                                          \
  "  return vec2(1.0, 1.0 - exp(-u_plain_opacity * m.a));\n"                   \
  "}\n"


/* Compiled twice: with EXACT defined, fragments go to per-pixel arrays
 * resolved by satf_glsl_resolve_fs; without, the colour is written for
 * fixed-function "over" blending in a structured order (renderer.c). */
const char *const satf_glsl_shade_fs =
    GLSL_VERSION
    "#ifndef EXACT\n"
    "#define EXACT 1\n"
    "#endif\n"
    MAP_FETCH
    "uniform int u_nlights;\n"
    "uniform vec3 u_light_color[4];\n"
    "uniform float u_kdif, u_kspe1, u_kspe2, u_exp1, u_exp2;\n"
    "uniform vec3 u_fdif, u_fspe1, u_fspe2;\n"
    "uniform float u_kshadow, u_noise;\n"
    "uniform int u_secondary, u_self_shadow;\n"
    "in vec4 v_diffuse;\n"
    "in vec4 v_spec1;\n"
    "in vec4 v_spec2;\n"
    "in float v_dom;\n"
    "/* paper 002's noise texture, as a hash: one value per strand-wide\n"
    " * column of the layer, varying slowly along t (a texture fetch costs\n"
    " * more than this on a CPU rasteriser) */\n"
    "float hash(vec2 p) {\n"
    "  return fract(sin(dot(p, vec2(127.1, 311.7))) * 43758.5453);\n"
    "}\n"
    "float strand_noise(vec2 uv) {\n"
    "  float col = floor(uv.x * 1024.0);\n"
    "  float y = uv.y * 6.0, row = floor(y);\n"
    "  return mix(hash(vec2(col, row)), hash(vec2(col, row + 1.0)),\n"
    "             smoothstep(0.0, 1.0, y - row));\n"
    "}\n"
    "uniform int u_aov;              /* 0 beauty, 1 diffuse, 2 specI, 3 specII,\n"
    "                                   4 shadow, 5 alpha */\n"
    "#if EXACT\n"
    "uniform int u_slots;            /* fragments a pixel can keep */\n"
    "layout(binding = 0, r32ui) uniform coherent uimage2D u_counts;\n"
    "layout(binding = 1, rgba32ui) uniform writeonly uimage2DArray u_frags;\n"
    "#else\n"
    "out vec4 o_color;\n"
    "#endif\n"
    "void main() {\n"
    "  vec4 m = fetch_map();\n"
    "  vec2 ra = reflectance_alpha(m);\n"
    "  float alpha = ra.y;\n"
    "#if EXACT\n"
    "  if (alpha < 1.0 / 1024.0) return;\n"
    "#else\n"
    "  if (alpha < 1.0 / 1024.0) discard;\n"
    "#endif\n"
    "  /* SATF eq. 12: exponential s-map from the outer layers' alpha */\n"
    "  float tau = u_self_shadow != 0 ? exp(-u_kshadow * m.b) : 1.0;\n"
    "  float dom = v_dom;\n"
    "  /* paper 002: noise breaks up the secondary highlight */\n"
    "  float nz = strand_noise(v_uv);\n"
    "  float noise = mix(1.0, 2.0 * nz, u_noise);\n"
    "  vec3 dif = vec3(0.0), s1 = vec3(0.0), s2 = vec3(0.0);\n"
    "  for (int k = 0; k < u_nlights; k++) {\n"
    "    vec3 c = u_light_color[k] * (k == 0 ? dom : 1.0);\n"
    "    dif += c * u_kdif * v_diffuse[k] * u_fdif;\n"
    "    s1 += c * u_kspe1 * pow(max(v_spec1[k], 0.0), u_exp1) * u_fspe1;\n"
    "    if (u_secondary != 0)\n"
    "      s2 += c * u_kspe2 * pow(max(v_spec2[k], 0.0), u_exp2) * u_fspe2 * noise;\n"
    "  }\n"
    "  /* SATF eq. 8 and 13: lighting x reflectance x transmittance */\n"
    "  float k = ra.x * tau;\n"
    "  vec3 c;\n"
    "  if (u_aov == 1) c = dif * k;\n"
    "  else if (u_aov == 2) c = s1 * k;\n"
    "  else if (u_aov == 3) c = s2 * k;\n"
    "  else if (u_aov == 4) c = vec3(tau * dom);\n"
    "  else if (u_aov == 5) c = vec3(1.0);\n"
    "  else c = (dif + s1 + s2) * k;\n"
    "  vec4 premul = vec4(c * alpha, alpha);\n"
    "#if EXACT\n"
    "  /* per-pixel fragment arrays: a slot from the pixel's own counter */\n"
    "  ivec2 px = ivec2(gl_FragCoord.xy);\n"
    "  int slot = int(imageAtomicAdd(u_counts, px, 1u));\n"
    "  if (slot >= u_slots) return;\n"
    "  imageStore(u_frags, ivec3(px, slot),\n"
    "             uvec4(packHalf2x16(premul.rg), packHalf2x16(premul.ba),\n"
    "                   floatBitsToUint(gl_FragCoord.z), 0u));\n"
    "#else\n"
    "  o_color = premul;\n"
    "#endif\n"
    "}\n";

const char *const satf_glsl_depth_fs =
    GLSL_VERSION MAP_FETCH
    "void main() {\n"
    "  if (reflectance_alpha(fetch_map()).y < 1.0 / 64.0) discard;\n"
    "}\n";

const char *const satf_glsl_dom_fs =
    GLSL_VERSION MAP_FETCH
    "uniform sampler2D u_dom_depth;\n"
    "uniform int u_layers;\n"
    "uniform float u_dom_slab;\n"
    "out vec4 o_opacity;\n"
    "void main() {\n"
    "  /* drawn for the outermost layer only: the innermost layer's s-map sum\n"
    "   * plus its own alpha is the alpha of every layer at this (u, t) */\n"
    "  vec4 m = fetch_layer(0);\n"
    "  float a = u_satf != 0 ? m.b + m.g : reflectance_alpha(m).y * float(u_layers);\n"
    "  float d0 = texelFetch(u_dom_depth, ivec2(gl_FragCoord.xy), 0).r;\n"
    "  float s = max(gl_FragCoord.z - d0, 0.0) / u_dom_slab;\n"
    "  int slab = int(min(s, 3.0));\n"
    "  vec4 o = vec4(0.0);\n"
    "  o[slab] = a; /* summed alpha ~ optical depth, adds along the ray */\n"
    "  o_opacity = o;\n"
    "}\n";

const char *const satf_glsl_fullscreen_vs =
    GLSL_VERSION
    "out vec2 v_uv;\n"
    "void main() {\n"
    "  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));\n"
    "  v_uv = p;\n"
    "  gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);\n"
    "}\n";

#define STR2(x) #x
#define STR(x) STR2(x)

const char *const satf_glsl_resolve_fs =
    GLSL_VERSION
    "#define MAXF " STR(SATF_MAX_FRAGMENTS) "\n"
    "layout(binding = 0, r32ui) uniform readonly uimage2D u_counts;\n"
    "layout(binding = 1, rgba32ui) uniform readonly uimage2DArray u_frags;\n"
    "uniform int u_slots;\n"
    "uniform vec3 u_background;\n"
    "uniform int u_use_background;\n"
    "out vec4 o_color;\n"
    "/* far before near; equal depths ordered by colour bits so the result\n"
    " * does not depend on the order fragments arrived in */\n"
    "bool farther(uvec4 a, uvec4 b) {\n"
    "  float da = uintBitsToFloat(a.z), db = uintBitsToFloat(b.z);\n"
    "  if (da != db) return da > db;\n"
    "  if (a.x != b.x) return a.x > b.x;\n"
    "  return a.y > b.y;\n"
    "}\n"
    "void main() {\n"
    "  uvec4 f[MAXF];\n"
    "  ivec2 px = ivec2(gl_FragCoord.xy);\n"
    "  int n = min(int(imageLoad(u_counts, px).r), min(u_slots, MAXF));\n"
    "  for (int k = 0; k < n; k++) f[k] = imageLoad(u_frags, ivec3(px, k));\n"
    "  for (int a = 1; a < n; a++) {\n"
    "    uvec4 x = f[a];\n"
    "    int b = a - 1;\n"
    "    while (b >= 0 && farther(x, f[b])) { f[b + 1] = f[b]; b--; }\n"
    "    f[b + 1] = x;\n"
    "  }\n"
    "  /* SATF eq. 14 over every layer of every cluster, back to front */\n"
    "  vec3 c = u_use_background != 0 ? u_background : vec3(0.0);\n"
    "  float transmit = 1.0;\n"
    "  for (int a = 0; a < n; a++) {\n"
    "    vec4 p = vec4(unpackHalf2x16(f[a].x), unpackHalf2x16(f[a].y));\n"
    "    c = c * (1.0 - p.a) + p.rgb;\n"
    "    transmit *= 1.0 - p.a;\n"
    "  }\n"
    "  o_color = vec4(c, 1.0 - transmit);\n"
    "}\n";

const char *const satf_glsl_display_fs =
    GLSL_VERSION
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
