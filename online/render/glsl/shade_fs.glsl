#version 430 core
/* shade_fs.glsl - SATF eq. 8-14 along each ray. Formulas cite SATF
 * (paper 001) and Scheuermann (paper 002).
 *
 * How a cluster is drawn. Only the front faces of its outermost shell are
 * rasterised; each fragment follows its eye ray through the nested shells
 * analytically and composites, front to back, the layer points P(u,v),k it
 * meets: the front half of every shell from the outside in, then the back
 * half (seen through the transparent core) from the inside out. This is
 * SATF eq. 13-14 evaluated at exactly the points the paper's per-layer
 * blending would blend, but one fragment per pixel and cluster does the
 * work of 2L, which on a CPU rasteriser is several times faster than
 * drawing every layer mesh. The local geometry is the generalized
 * cylinder's: at the fragment's t the shells are the ellipses
 * v (A cos, B sin) (eq. 1), which in coordinates scaled by 1/A, 1/B are
 * circles of radius v.
 *
 * Compiled twice: with EXACT defined, each fragment (one cluster's
 * composite along the pixel's ray) goes to per-pixel arrays resolved by
 * resolve_fs.glsl; without, it is written for fixed-function "over"
 * blending of clusters drawn far to near. The renderer defines
 * SATF_MAX_LIGHTS (the scene format's light limit) and NLIGHTS. */
#ifndef EXACT
#define EXACT 1
#endif
#ifndef NLIGHTS /* the renderer defines the scene's light count */
#define NLIGHTS 1
#endif
/* 1: the physical mode (maps_fiber.h): the maps hold each layer point's
 * radiance from the fibre database and model, two slices per layer */
#ifndef PHYSICAL
#define PHYSICAL 0
#endif
#include "map_fetch.glsl"
#include "lighting.glsl"
#if PHYSICAL
#include "fiber_cluster.glsl"
in vec3 v_global; /* the key light's global scattering (cluster_vs.glsl) */
in vec3 v_back;
/* the fill light's, and its map's transmittance where its light enters
 * the cluster, per vertex (cluster_vs.glsl) */
in vec3 v_fill_global, v_fill_back;
in float v_fill_dom;
#endif
in vec3 v_local;
in vec3 v_world;
in vec3 v_hair;
in float v_t;
in vec3 v_centre;
in vec3 v_n1;
in vec3 v_n2;
in vec4 v_shape;
in vec3 v_axis;
/* Per instance (one draw shades a run of them: cluster_vs.glsl): its
 * prototype -> world transform, and the eye and lights (xyz, w: 0
 * direction to the light, 1 position) in the prototype's frame. */
flat in int v_instance;
layout(std430, binding = 3) readonly buffer satf_models { mat4 g_model[]; };
struct satf_view { vec4 eye; vec4 light[SATF_MAX_LIGHTS]; };
layout(std430, binding = 4) readonly buffer satf_views { satf_view g_view[]; };
/* read once per fragment (load_instance), not at every use */
mat4 u_model;
vec3 u_eye_local;
vec4 u_light_local[SATF_MAX_LIGHTS];
float u_lod; /* the level of detail (lod.c), in the eye's w */
void load_instance() {
  u_model = g_model[v_instance];
  u_eye_local = g_view[v_instance].eye.xyz;
  u_lod = g_view[v_instance].eye.w;
  for (int k = 0; k < NLIGHTS; k++) u_light_local[k] = g_view[v_instance].light[k];
}
uniform int u_nlights;
uniform vec3 u_light_color[SATF_MAX_LIGHTS];
uniform int u_layers;
uniform float u_core;
uniform float u_kdif, u_kspe1, u_kspe2, u_exp1, u_exp2, u_shift1, u_shift2;
uniform vec3 u_fdif, u_fspe1, u_fspe2;
uniform float u_kshadow, u_noise;
uniform int u_secondary, u_self_shadow, u_cluster_shadow, u_fill_shadow;
uniform sampler2D u_dom_depth;
uniform sampler2D u_dom_opacity;
uniform mat4 u_light_viewproj;
uniform float u_dom_slab;
uniform float u_kcluster;
uniform int u_aov;  /* 0 beauty, 1 diffuse, 2 specI, 3 specII, 4 shadow, 5 alpha */
#if EXACT
#include "list_write.glsl"
/* the nearest-kept passes' first (cluster_gpu_lists) wants only the depth key
 * of each fragment that would be stored: its alpha, which the maps' alpha
 * alone decides, not its colour (no lighting, no shadows) */
#define KEYS_ONLY (u_list_mode == 1)
#else
out vec4 o_color;
#define KEYS_ONLY false
#endif
/* paper 002's noise texture, as an integer hash: one value per
 * strand-wide column, varying slowly along t */
float hash(uint x) {
  x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu;
  x ^= x >> 16;
  return float(x >> 8) * (1.0 / 16777216.0);
}
float strand_noise(float u_turns, float t) {
  uint col = uint(fract(u_turns) * 1024.0);
  float y = clamp(t, 0.0, 1.0) * 6.0, row = floor(y);
  uint r = uint(row);
  return mix(hash(col * 8u + r), hash(col * 8u + r + 1u), y - row);
}
/* atan2 in turns ([-1/2, 1/2]), a 5th-order minimax fit good to 1e-5
 * turns: a map texel is 1e-3 turns wide, and the exact atan costs
 * several times more on a CPU rasteriser */
float atan2_turns(float y, float x) {
  float ax = abs(x), ay = abs(y);
  float a = min(ax, ay) / max(max(ax, ay), 1e-30);
  float s = a * a;
  float r = ((-0.0464964749 * s + 0.15931422) * s - 0.327622764) * s * a + a;
  if (ay > ax) r = 1.57079637 - r;
  if (x < 0.0) r = 3.14159274 - r;
  if (y < 0.0) r = -r;
  return r * 0.159154943;
}
/* Deep opacity map (Yuksel & Keyser 2008): optical depth of hair between
 * the key light and this point, from four slabs behind the first hair. */
#include "dom_lookup.glsl"
#include "shell_entry.glsl"
/* Who owns self-shadowing: the records own the attenuation among the
 * strands of one HSV (traced in the sector, paper 001 sec. 4), eq. 12's
 * s-map owns the attenuation by this cluster's outer layers (in the
 * physical mode with the rest of its own layers the light crosses:
 * through_layers), and the deep opacity map owns the other clusters. So
 * the map is read where the key light's ray towards this point enters the
 * cluster (its exit from the outermost ellipse, in the scaled normal-plane
 * coordinates P of main, taken within the widest chord of the point:
 * shell_entry.glsl), moved out by a tenth of the cluster's radius: the
 * map's proxies circumscribe the shell coarsely, and the cluster's own
 * slab must not be counted a second (or third) time. A lone cluster is
 * the first hair there, so the map leaves it unlit by nothing
 * (tests/render/test_correctness.c). */
float key_light_dom(vec2 P, vec3 n1, vec3 n2, float A, float B) {
  vec3 l = normalize(u_light_local[0].xyz - u_light_local[0].w * v_local);
  vec3 entry = shell_entry(v_local, P, l, n1, n2, A, B);
  return cluster_transmittance((u_model * vec4(entry, 1.0)).xyz);
}
/* SATF eq. 8-11 at a layer point: diffuse, primary and secondary
 * highlight (the latter without its noise factor), n the normal the
 * highlights shift along */
void lighting(vec3 t, vec3 n, vec3 v, float dom, out vec3 dif,
              out vec3 s1, out vec3 s2) {
  dif = s1 = s2 = vec3(0.0);
  vec3 t1 = shifted(t, n, u_shift1), t2 = shifted(t, n, -u_shift2);
  for (int k = 0; k < NLIGHTS; k++) {
    vec3 dl = u_light_local[k].xyz - u_light_local[k].w * v_local;
    vec3 l = normalize(dl);
    /* point lights fall off as 1 / d^2 (samples/README.md) */
    float fall = u_light_local[k].w > 0.0 ? 1.0 / max(dot(dl, dl), 1e-6) : 1.0;
    vec3 c = u_light_color[k] * fall * (k == 0 ? dom : 1.0);
    dif += c * u_kdif * kk_diffuse(t, l) * u_fdif;
    s1 += c * u_kspe1 * kk_specular(t1, l, v, u_exp1) * u_fspe1;
    if (u_secondary != 0)
      s2 += c * u_kspe2 * kk_specular(t2, l, v, u_exp2) * u_fspe2;
  }
}
/* Level of detail (lod.c): at level n + f every 2^n-th shell from the
 * outermost is read and stands for the 2^n inwards of it, the ones level
 * n + 1 drops with weight 1 - f, their share going to the ones it keeps
 * (lod_layer_share: the same). A read shell's alpha a becomes that of the
 * `share` layers it stands for, 1 - (1 - a)^share (SATF eq. 14 over equal
 * layers). Compiled in only with LOD 1 (the renderer's --lod): llvmpipe
 * runs both sides of a branch its lanes could take apart, so these cost
 * every layer point their integer and exp2/log2 work even at level 0
 * (14% of the shading pass of cluster_6a). */
#ifndef LOD
#define LOD 1
#endif
bool lod_read(int k) {
#if LOD
  /* j % 2^n as j & (2^n - 1), j >= 0: llvmpipe divides integer vectors
   * lane by lane */
  return u_lod <= 0.0 || ((u_layers - 1 - k) & ((1 << int(u_lod)) - 1)) == 0;
#else
  return true;
#endif
}
float lod_alpha(int k, float a) {
#if LOD
  if (u_lod <= 0.0) return a;
  int n = int(u_lod), m1 = 1 << n, m2 = m1 << 1;
  float f = u_lod - float(n);
  int j = u_layers - 1 - k, left = u_layers - j, own = min(m1, left);
  float share = (j & (m2 - 1)) == 0
                    ? float(own) + f * float(clamp(left - m1, 0, m1))
                    : (1.0 - f) * float(own);
  return 1.0 - exp2(share * log2(max(1.0 - a, 1e-6)));
#else
  return a;
#endif
}
/* How many of its cluster's layers a light crosses on its way to the layer
 * point at radius r of shell k beyond those eq. 12's s-map counts (the
 * layers outside k, once each) and the point's own record holds (its own
 * layer on the near side). Where the light runs towards the axis from the
 * point (it comes from across the cluster: X.L < 0), its line dips q
 * layers deep below the point, down to the hollow core, and leaves
 * through the far side of shell k: within the point's own layer it
 * crosses that layer once more, and for each layer deeper that layer
 * twice and the one where it turns back out once: 1, 2, 4, 6 ... up to
 * 2k + 1 through the core (layer j lies between r_(j-1) and r_j, r_j =
 * core + (1 - core)(j + 1) / layers, circles in the scaled normal plane).
 * The count is taken linear in q between the layers' middles, so the
 * light changes continuously with its direction (whole crossings stepped
 * it at every shell's tangent); the chord's length through the layers,
 * which weighs a light skimming a layer heavily, came out darker against
 * Cycles (docs/shading.md, a cluster lit through itself). The deep
 * opacity map is read at most `cap` along the light from the fragment
 * (shell_entry), beyond which it counts the cluster's hair itself, so the
 * count is scaled to the part of the path within the cap. xl: X.L,
 * inv_al: 1 / |L|^2 (L the unit light direction projected into the scaled
 * plane), shells: layers / (1 - core). Our addition: SATF's eq. 12 is the
 * outer layers' alpha alone, the same from either side. */
float through_layers(float r, float xl, float inv_al, float shells,
                     float cap, int k) {
  if (xl >= 0.0) return 0.0;
  float d = sqrt(max(r * r - xl * xl * inv_al, 0.0));
  /* how many layers deep the line dips, down to the hollow core */
  float q = (r - max(d, u_core)) * shells;
  /* the path to the far side of shell k, in scene units along the light */
  float path = -2.0 * xl * inv_al;
  /* through (0, 0), (1/2, 1), (3/2, 2), (5/2, 4), (7/2, 6) ... */
  float n = max(min(2.0 * q, q + 0.5), 2.0 * q - 1.0);
  return min(n, 2.0 * float(k) + 1.0) * min(cap / max(path, 1e-12), 1.0);
}
/* A light's Poisson count of this cluster's hairs in front of the layer
 * point at s along the eye ray: eq. 12's outer layers (`outer`) and, when
 * `through`, the layers it crosses (thru: X.L = thru.x + s thru.y, and
 * 1 / |L|^2), each at the layer's own `alpha`. */
float self_hairs(vec3 thru, float s, float r, float shells, float cap, int k,
                 float outer, float alpha, bool through) {
  return outer + (through ? through_layers(r, thru.x + s * thru.y, thru.z,
                                           shells, cap, k) *
                                alpha
                          : 0.0);
}
/* The light a cluster's hair scatters forward to the layer points a ray
 * meets (Zinke 2008): e_global x (exp(-n (1 - a_f)) - exp(-n)) for n the
 * point's Poisson count of hairs towards the light, the map's (n_map) and
 * its own cluster's, summed over the points with weights w (transmittance
 * to the point x its alpha). Taken at the weighted mean count: w_sum x
 * the term at n_map + n_sum / w_sum. Our approximation: taken at every
 * point it cost six exponentials a point, about 40 ms of the shared
 * ponytail's physical frame on llvmpipe, and the counts along one ray lie
 * close together (docs/shading.md, docs/performance.md "Physical against
 * kk"). */
vec3 forward_scattered(vec3 e_global, float n_map, vec3 af, float w_sum,
                       float n_sum) {
  if (w_sum <= 0.0) return vec3(0.0);
  float n = n_map + n_sum / w_sum;
  return w_sum * e_global *
         max(exp(-n * (1.0 - af)) - exp(-n), vec3(0.0));
}
vec3 select_aov(vec3 dif, vec3 s1, vec3 s2) {
  if (u_aov == 1) return dif;
  if (u_aov == 2) return s1;
  if (u_aov == 3) return s2;
  return dif + s1 + s2;
}
void main() {
  load_instance();
  /* n1, n2 are the ellipse's axes, already turned by the twist (SATF
   * eq. 1, satf/geometry.h): the phase u is the angle from n1 */
  float A = v_shape.x, B = v_shape.y;
  vec3 n1 = normalize(v_n1), n2 = normalize(v_n2), axis = normalize(v_axis);
  vec3 d = normalize(v_local - u_eye_local);
  vec3 q = v_local - v_centre;
  /* the ray in the normal plane, scaled so the shells are circles */
  vec2 P = vec2(dot(q, n1) / A, dot(q, n2) / B);
  vec2 D = vec2(dot(d, n1) / A, dot(d, n2) / B);
  float dt_ds = dot(d, axis) / max(v_shape.w, 1e-6);
  float a = max(dot(D, D), 1e-12), b = dot(P, D), c0 = dot(P, P);
  vec3 hair = normalize(v_hair), v = -d;
  float dom = 1.0;
  if (u_cluster_shadow != 0 && !KEYS_ONLY)
    dom = key_light_dom(P, n1, n2, A, B);
  vec3 df, s1f, s2f;
#if !PHYSICAL
  /* SATF eq. 10-11 shift the primary highlight towards the tip and the
   * secondary towards the root along a normal of the hair. We take the
   * strand's normal facing the viewer (lighting.glsl: facing_normal), as
   * the strand reference path does, for every layer point on the ray,
   * front and back, so one lighting serves them all. The cluster's ellipse
   * normal, used before, turns across the cluster (sideways at its
   * silhouette, where it tilts the tangent across the view instead of
   * along it), so the highlight of parallel strands moved across a flat
   * cluster (test_render: 0.84-1.01 of its mean, now within 0.3%); at the
   * back the outward normal swapped the two highlights and lit the strands
   * seen through a sparse cluster white, hence the inward one there. */
  if (!KEYS_ONLY) lighting(hair, facing_normal(hair, v), v, dom, df, s1f, s2f);
#else
  /* the key light's irradiance, direction, and the hairs of other clusters
   * in front of the point (the deep opacity map's transmittance as a
   * Poisson count) */
  vec3 dl0 = u_light_local[0].xyz - u_light_local[0].w * v_local;
  vec3 l0 = normalize(dl0);
  vec3 e0 = u_light_color[0] *
            (u_light_local[0].w > 0.0 ? 1.0 / max(dot(dl0, dl0), 1e-6) : 1.0);
  float n_dom = -log(max(dom, 1e-6));
  /* the direct light's local back-scattering from the hair behind the
   * point (Zinke's eq. 20: f_s + d_b f_back; the records hold what the
   * point's own sector scatters back) */
  vec3 global = v_global, back = FIBER_DUAL_DENSITY * e0 * v_back;
  /* a_f of the tables at the light's inclination, once per fragment: each
   * layer point only takes its depth's transmittance (Zinke's eq. 5) */
  vec3 af0 = fiber_dual_field(u_fiber_tables, 0,
                              fiber_asin(clamp(dot(l0, hair), -1.0, 1.0)));
  /* the key light's direction in the scaled normal plane, for the
   * layers it crosses on its way to each point (through_layers) */
  vec2 Lk = vec2(dot(l0, n1) / A, dot(l0, n2) / B);
  /* X.L = P.L + s D.L along the eye ray, and 1 / |L|^2 */
  vec3 thru0 = vec3(dot(P, Lk), dot(D, Lk), 1.0 / max(dot(Lk, Lk), 1e-12));
  float shells = float(u_layers) / max(1.0 - u_core, 1e-6);
  float cap = SHELL_ENTRY_MAX_CHORDS * 2.0 * max(A, B);
  bool through = u_self_shadow != 0 && !KEYS_ONLY;
  /* the fill light (and those after it, whose light the maps sum with
   * the fill's) the same way through its own map, where it is drawn */
  bool fill_shadow = u_fill_shadow != 0 && NLIGHTS > 1 && !KEYS_ONLY;
  float n_fill = 0.0;
  vec3 e1 = vec3(0.0), back1 = vec3(0.0), af1 = vec3(0.0);
  vec3 thru1 = vec3(0.0);
  if (fill_shadow) {
    int k1 = NLIGHTS > 1 ? 1 : 0;
    vec3 dl1 = u_light_local[k1].xyz - u_light_local[k1].w * v_local;
    e1 = u_light_color[k1] *
         (u_light_local[k1].w > 0.0 ? 1.0 / max(dot(dl1, dl1), 1e-6) : 1.0);
    n_fill = -log(max(v_fill_dom, 1e-6));
    back1 = FIBER_DUAL_DENSITY * e1 * v_fill_back;
    vec3 l1 = normalize(dl1);
    af1 = fiber_dual_field(u_fiber_tables, 0,
                           fiber_asin(clamp(dot(l1, hair), -1.0, 1.0)));
    vec2 Lf = vec2(dot(l1, n1) / A, dot(l1, n2) / B);
    thru1 = vec3(dot(P, Lf), dot(D, Lf), 1.0 / max(dot(Lf, Lf), 1e-12));
  }
#endif
  vec3 col = vec3(0.0);
  float transmit = 1.0;
#if !PHYSICAL
  /* SATF eq. 13 makes a layer point's colour the fragment's lighting L
   * (one per ray, above) times a scalar, the point's reflectance and
   * s-map shadow, so eq. 14's sum is L times the sum of the scalars: the
   * loop sums one float per point, and the noise (of the first point that
   * counts) scales L's secondary highlight once, after it */
  float weight = 0.0, noise_u = 0.0, noise_t = -1.0;
#endif
#if PHYSICAL
  /* the forward-scattered light's weights (transmit x alpha of the layer
   * points) and weighted self counts, key and fill: forward_scattered */
  float fw_w = 0.0, fw_n = 0.0, fw1_w = 0.0, fw1_n = 0.0;
#endif
  int inner = 0;  /* innermost shell the ray meets */
  /* the loop's divisions, hoisted */
  float inv_layers = 1.0 / float(u_layers), inv_a = 1.0 / a;
  /* SATF eq. 14 front to back: the front halves, outer to inner, then
   * the back halves, inner to outer */
  for (int pass = 0; pass < 2; pass++) {
    for (int j = 0; j < u_layers; j++) {
      int k = pass == 0 ? u_layers - 1 - j : inner + j;
      if (k >= u_layers) break;
      if (!lod_read(k)) continue;
      float r = u_core + (1.0 - u_core) * float(k + 1) * inv_layers;
      float disc = b * b - a * (c0 - r * r);
      if (disc <= 0.0) { inner = k + 1; break; }
      float s = (-b + (pass == 0 ? -1.0 : 1.0) * sqrt(disc)) * inv_a;
      vec2 X = P + s * D;
      float u_turns = atan2_turns(X.y, X.x);
      float t = v_t + s * dt_ds;
      /* the cluster ends at t = 0 and 1: a ray that leaves through an end
       * meets no strands there (clamping t would shade a phantom cap with
       * the end row) */
      if (t < 0.0 || t > 1.0) continue;
#if PHYSICAL
      /* the key light's radiance and alpha; the other lights' and the
       * s-map sum (maps_fiber.h) */
      vec4 mk, mf;
      fetch_maps(u_turns, t, k, mk, mf);
      vec2 ra = vec2(1.0, lod_alpha(k, mk.a));
      if (ra.y < 1.0 / 1024.0) continue;
      /* the direct light crosses the outer layers' hairs, and those of
       * its cluster it meets on its way (through_layers), as a Poisson
       * count (exp(-n), Zinke's model; the paper's k_shadow belongs to
       * the kk mode); each layer crossed at this one's own alpha */
      float n_self =
          self_hairs(thru0, s, r, shells, cap, k, mf.a, mk.a, through);
      float tau = u_self_shadow != 0 ? exp(-n_self) : 1.0;
#else
      vec4 m = fetch_map(u_turns, t, k);
      vec2 ra = reflectance_alpha(m);
      ra.y = lod_alpha(k, ra.y);
      if (ra.y < 1.0 / 1024.0) continue;
      /* SATF eq. 12: exponential s-map from the outer layers' alpha */
      float tau = u_self_shadow != 0 ? exp(-u_kshadow * m.b) : 1.0;
#endif
#if PHYSICAL
      vec3 y;
      if (KEYS_ONLY) y = vec3(0.0);
      else if (u_aov == 4) y = vec3(tau * dom);
      else if (u_aov == 5) y = vec3(1.0);
      else {
        /* the key light shadowed by this cluster's layers (eq. 12 and
         * through_layers) and the other clusters (deep opacity map); the
         * records hold the shadowing inside an HSV */
        y = (mk.rgb + back) * (tau * dom);
        float w = transmit * ra.y;
        if (u_cluster_shadow != 0) { /* forward-scattered: after the loop */
          fw_w += w;
          fw_n += w * n_self;
        }
        if (fill_shadow) { /* the fill light through its own path */
          float n1_self =
              self_hairs(thru1, s, r, shells, cap, k, mf.a, mk.a, through);
          float tau1 = u_self_shadow != 0 ? exp(-n1_self) : 1.0;
          y += (mf.rgb + back1) * (tau1 * exp(-n_fill));
          fw1_w += w;
          fw1_n += w * n1_self;
        } else
          y += mf.rgb;
      }
      col += transmit * ra.y * y;
#else
      /* the point's share of L (SATF eq. 13): the AOVs shadow (4) and
       * alpha (5) take tau and 1, with L = dom and 1 below */
      float g = u_aov == 5 ? 1.0 : u_aov == 4 ? tau : ra.x * tau;
      weight += transmit * ra.y * g;
      if (noise_t < 0.0) { /* the strands the ray meets first */
        noise_u = u_turns;
        noise_t = t;
      }
#endif
      transmit *= 1.0 - ra.y;
      /* what lies behind can change the pixel by less than 1/512 */
      if (transmit < 1.0 / 512.0) break;
    }
    if (transmit < 1.0 / 512.0) break;
  }
  float alpha = 1.0 - transmit;
#if PHYSICAL
  col += forward_scattered(e0 * global, n_dom, af0, fw_w, fw_n) +
         forward_scattered(e1 * v_fill_global, n_fill, af1, fw1_w, fw1_n);
#endif
#if !PHYSICAL
  if (KEYS_ONLY) col = vec3(0.0);
  else if (u_aov == 4) col = vec3(weight * dom);
  else if (u_aov == 5) col = vec3(weight);
  else {
    float noise = mix(1.0, 2.0 * strand_noise(noise_u, noise_t), u_noise);
    col = select_aov(df, s1f, s2f * noise) * weight;
  }
#endif
#if EXACT
  if (alpha < 1.0 / 1024.0) return;
  list_write(col, alpha);
#else
  if (alpha < 1.0 / 1024.0) discard;
  o_color = vec4(col, alpha);
#endif
}
