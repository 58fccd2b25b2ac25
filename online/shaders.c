/* shaders.c - GLSL of the online renderer. Formulas cite SATF (paper 001)
 * and Scheuermann (paper 002). */
#include "online/shaders.h"

#define GLSL_VERSION "#version 430 core\n"

const char *const satf_glsl_layer_vs =
    GLSL_VERSION
    "layout(location = 0) in vec3 a_pos;\n"
    "layout(location = 1) in vec3 a_normal;\n"
    "layout(location = 2) in vec3 a_tangent;\n"
    "layout(location = 3) in vec2 a_uv;\n"
    "uniform mat4 u_model;\n"
    "uniform mat3 u_normal_matrix;\n"
    "uniform mat4 u_viewproj;\n"
    "out vec3 v_world;\n"
    "out vec3 v_normal;\n"
    "out vec3 v_tangent;\n"
    "out vec2 v_uv;\n"
    "void main() {\n"
    "  vec4 w = u_model * vec4(a_pos, 1.0);\n"
    "  v_world = w.xyz;\n"
    "  v_normal = u_normal_matrix * a_normal;\n"
    "  v_tangent = mat3(u_model) * a_tangent;\n"
    "  v_uv = a_uv;\n"
    "  gl_Position = u_viewproj * w;\n"
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
  "/* rows 2i and 2i+1 hold HSV i's two boundary records: a linear fetch\n"    \
  " * between them is SATF eq. 7 with g the position along the HSV */\n"      \
  "vec4 fetch_map() {\n"                                                       \
  "  float ts = clamp(v_uv.y, 0.0, 1.0) * float(u_st);\n"                      \
  "  float i = min(floor(ts), float(u_st - 1));\n"                             \
  "  float y = (2.0 * i + 0.5 + (ts - i)) / (2.0 * float(u_st));\n"            \
  "  return texture(u_maps, vec3(v_uv.x, y, float(u_layer)));\n"               \
  "}\n"                                                                        \
  "/* SATF maps give reflectance and alpha; the plain mode (paper 002) has\n"  \
  " * unit reflectance and an opacity from the mean density alone */\n"       \
  "vec2 reflectance_alpha(vec4 m) {\n"                                         \
  "  if (u_satf != 0) return m.rg;\n"                                          \
  "  return vec2(1.0, 1.0 - exp(-u_plain_opacity * m.a));\n"                   \
  "}\n"

const char *const satf_glsl_shade_fs =
    GLSL_VERSION MAP_FETCH
    "uniform vec3 u_eye;\n"
    "uniform int u_nlights;\n"
    "uniform vec4 u_light_vec[4];   /* xyz, w: 0 direction to light, 1 position */\n"
    "uniform vec3 u_light_color[4];\n"
    "uniform float u_kdif, u_kspe1, u_kspe2, u_exp1, u_exp2, u_shift1, u_shift2;\n"
    "uniform vec3 u_fdif, u_fspe1, u_fspe2;\n"
    "uniform float u_kshadow, u_noise;\n"
    "uniform int u_secondary, u_self_shadow, u_cluster_shadow;\n"
    "uniform sampler2D u_noise_tex;\n"
    "uniform sampler2D u_dom_depth;\n"
    "uniform sampler2D u_dom_opacity;\n"
    "uniform mat4 u_light_viewproj;\n"
    "uniform float u_dom_slab;       /* slab depth in light depth units */\n"
    "uniform float u_kcluster;\n"
    "uniform int u_aov;              /* 0 beauty, 1 diffuse, 2 specI, 3 specII,\n"
    "                                   4 shadow, 5 alpha */\n"
    "uniform int u_slots;            /* fragments a pixel can keep */\n"
    "layout(binding = 0, r32ui) uniform coherent uimage2D u_counts;\n"
    "layout(binding = 1, rgba32ui) uniform writeonly uimage2DArray u_frags;\n"
    "float sin_between(vec3 a, vec3 b) {\n"
    "  float c = dot(a, b);\n"
    "  return sqrt(max(0.0, 1.0 - c * c));\n"
    "}\n"
    "/* SATF eq. 9: Kajiya-Kay diffuse */\n"
    "float kk_diffuse(vec3 t, vec3 l) { return sin_between(t, l); }\n"
    "/* SATF eq. 10-11 with the tangent shifted along the cluster normal\n"
    " * (paper 002: T' = normalize(T + s N)). The extracted eq. 10 reads\n"
    " * (t.l)(t.v) + sin sin; with v pointing to the viewer that peaks at\n"
    " * retro-reflection, so we use the mirror form sin sin - (t.l)(t.v)\n"
    " * (Kajiya-Kay measure the eye vector towards the surface). */\n"
    "float kk_specular(vec3 t, vec3 l, vec3 v, float e) {\n"
    "  float c = sin_between(t, l) * sin_between(t, v) - dot(t, l) * dot(t, v);\n"
    "  return pow(max(c, 0.0), e);\n"
    "}\n"
    "vec3 shifted(vec3 t, vec3 n, float s) { return normalize(t + s * n); }\n"
    "/* Deep opacity map (Yuksel & Keyser 2008): optical depth of hair between\n"
    " * the key light and this point, from four slabs behind the first hair. */\n"
    "float cluster_transmittance() {\n"
    "  vec4 p = u_light_viewproj * vec4(v_world, 1.0);\n"
    "  vec3 q = p.xyz / p.w * 0.5 + 0.5;\n"
    "  if (any(lessThan(q.xy, vec2(0.0))) || any(greaterThan(q.xy, vec2(1.0))))\n"
    "    return 1.0;\n"
    "  float d0 = texture(u_dom_depth, q.xy).r;\n"
    "  vec4 o = texture(u_dom_opacity, q.xy);\n"
    "  float s = max(q.z - d0, 0.0) / u_dom_slab;\n"
    "  float depth = o.x * clamp(s, 0.0, 1.0) + o.y * clamp(s - 1.0, 0.0, 1.0) +\n"
    "                o.z * clamp(s - 2.0, 0.0, 1.0) + o.w * clamp(s - 3.0, 0.0, 1.0);\n"
    "  return exp(-u_kcluster * depth);\n"
    "}\n"
    "void main() {\n"
    "  vec4 m = fetch_map();\n"
    "  vec2 ra = reflectance_alpha(m);\n"
    "  float alpha = ra.y;\n"
    "  if (alpha < 1.0 / 1024.0) return;\n"
    "  vec3 t = normalize(v_tangent);\n"
    "  vec3 n = normalize(v_normal);\n"
    "  vec3 v = normalize(u_eye - v_world);\n"
    "  /* SATF eq. 12: exponential s-map from the outer layers' alpha */\n"
    "  float tau = u_self_shadow != 0 ? exp(-u_kshadow * m.b) : 1.0;\n"
    "  float dom = u_cluster_shadow != 0 ? cluster_transmittance() : 1.0;\n"
    "  /* paper 002: noise breaks up the secondary highlight */\n"
    "  float nz = texture(u_noise_tex, v_uv * vec2(48.0, 3.0)).r;\n"
    "  float noise = mix(1.0, 2.0 * nz, u_noise);\n"
    "  vec3 dif = vec3(0.0), s1 = vec3(0.0), s2 = vec3(0.0);\n"
    "  for (int k = 0; k < u_nlights; k++) {\n"
    "    vec3 l = normalize(u_light_vec[k].xyz - u_light_vec[k].w * v_world);\n"
    "    vec3 c = u_light_color[k] * (k == 0 ? dom : 1.0);\n"
    "    dif += c * u_kdif * kk_diffuse(t, l) * u_fdif;\n"
    "    s1 += c * u_kspe1 * kk_specular(shifted(t, n, u_shift1), l, v, u_exp1) * u_fspe1;\n"
    "    if (u_secondary != 0)\n"
    "      s2 += c * u_kspe2 * kk_specular(shifted(t, n, -u_shift2), l, v, u_exp2) *\n"
    "            u_fspe2 * noise;\n"
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
    "  /* per-pixel fragment arrays: a slot from the pixel's own counter */\n"
    "  ivec2 px = ivec2(gl_FragCoord.xy);\n"
    "  int slot = int(imageAtomicAdd(u_counts, px, 1u));\n"
    "  if (slot >= u_slots) return;\n"
    "  imageStore(u_frags, ivec3(px, slot),\n"
    "             uvec4(packHalf2x16(premul.rg), packHalf2x16(premul.ba),\n"
    "                   floatBitsToUint(gl_FragCoord.z), 0u));\n"
    "}\n";

const char *const satf_glsl_depth_fs =
    GLSL_VERSION MAP_FETCH
    "void main() {\n"
    "  if (reflectance_alpha(fetch_map()).y < 1.0 / 64.0) discard;\n"
    "}\n";

const char *const satf_glsl_dom_fs =
    GLSL_VERSION MAP_FETCH
    "uniform sampler2D u_dom_depth;\n"
    "uniform vec2 u_dom_size;\n"
    "uniform float u_dom_slab;\n"
    "out vec4 o_opacity;\n"
    "void main() {\n"
    "  float a = min(reflectance_alpha(fetch_map()).y, 0.999);\n"
    "  float d0 = texture(u_dom_depth, gl_FragCoord.xy / u_dom_size).r;\n"
    "  float s = max(gl_FragCoord.z - d0, 0.0) / u_dom_slab;\n"
    "  int slab = int(min(s, 3.0));\n"
    "  vec4 o = vec4(0.0);\n"
    "  o[slab] = -log(1.0 - a); /* optical depth adds along the light ray */\n"
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
