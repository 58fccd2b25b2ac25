#version 430 core
/* maps_kk_cs.glsl - the paper's maps (SATF sec. 6.2: eq. 4, 6, 7) of the
 * instances whose eye or light moved, written straight into their
 * textures (maps_gpu.c): what maps.c's satf_maps_update_layer makes on the
 * CPU, value for value up to float rounding, in the layout of maps.h; the
 * s-map sums of eq. 12 follow (maps_sums_cs.glsl). One invocation per HSV
 * (i, k, j) of one instance (work group z: the instance's entry), which
 * lays its two rows column by column. No shared memory and no barrier:
 * llvmpipe runs a shader with barriers on coroutines, which cost it more
 * than the look-ups (cluster_6a: 85 of 110 ms with nothing else done).
 * The renderer defines MAPS_W (the records' width), MAPS_BINS (maps.h:
 * MAPS_AZIMUTH_BINS) and MAPS_K (the neighbours cached per look-up). */
layout(local_size_x = 64) in;

layout(rgba16f, binding = 0) uniform writeonly image2DArray u_maps;

/* the database's records, channels 0 (reflectance) and 1 (alpha) as
 * halfs, two to a word: record (sample, view iv, light il) starts at half
 * ((sample * n_light + il) * n_view + iv) * 2 MAPS_W */
layout(std430, binding = 0) readonly buffer maps_records { uint g_rec[]; };
/* per database sample: its level (maps.c: sample_re) */
layout(std430, binding = 2) readonly buffer maps_levels { float g_level[]; };
#include "maps_inst.glsl"
#include "maps_lookup.glsl"

uniform float u_re_scale;   /* maps.c: reflectance_scale */
uniform vec3 u_fscale;      /* 1 / each feature's range over the database */
uniform float u_threshold;  /* eq. 6 */

struct Params {
  vec3 f;
  float view, light;
};

Params sector_params(int q, vec3 eye, vec4 light) {
  int o = MAPS_SECTOR_FLOATS * q;
  vec3 p = vec3(g_sector[o], g_sector[o + 1], g_sector[o + 2]);
  Params s;
  s.f = vec3(g_sector[o + 9], g_sector[o + 10], g_sector[o + 11]);
  s.view = azimuth(q, eye - p);
  s.light = azimuth(q, light.xyz - light.w * p);
  return s;
}

/* maps.c: angle_diff, b - a into (-pi, pi]; both azimuths lie in
 * [0, 2 pi], so fmodf only takes a whole turn off */
float angle_diff(float a, float b) {
  float d = b - a;
  if (abs(d) >= TWO_PI)
    d -= sign(d) * TWO_PI;
  if (d > PI)
    d -= TWO_PI;
  if (d <= -PI)
    d += TWO_PI;
  return d;
}

float rec_half(int h) {
  uint w = g_rec[h >> 1];
  return unpackHalf2x16((h & 1) == 0 ? w : w >> 16).x;
}

/* One look-up (eq. 4) at (view, light) from the neighbours at entry nb:
 * where its four stored azimuth pairs start (as record offsets, in halfs)
 * and their weights (satf_db_lookup_cell_range's blend), the resampling
 * row of `view` (maps.c: maps_columns) and the neighbours' blended level
 * (orientation-free), else 0. */
struct Look {
  ivec4 corner;
  vec4 bw;
  int nb, bin;
  float level;
};

Look look_at(int nb, float view, float light, int free_level) {
  Look k;
  cell(view, light, 2 * MAPS_W, k.corner, k.bw);
  k.nb = nb * MAPS_K;
  k.bin = column_bin(view);
  float l = 0.0, wsum = 0.0;
  for (int n = 0; n < MAPS_K; n++) {
    uvec2 e = g_nb[k.nb + n];
    float w = uintBitsToFloat(e.y);
    if (w > 0.0 && g_level[e.x] > 0.0) {
      l += w * g_level[e.x];
      wsum += w;
    }
  }
  k.level = free_level != 0 && wsum > 0.0 ? l / wsum : 0.0;
  return k;
}

/* The looked-up record (satf_db_lookup_cell_range's blend: the
 * neighbours in order, each its four corners, as the CPU sums them), its
 * reflectance then its alpha; per invocation. */
float g_re[MAPS_W], g_al[MAPS_W];

void blend(Look k) {
  for (int s = 0; s < MAPS_W; s++) {
    g_re[s] = 0.0;
    g_al[s] = 0.0;
  }
  for (int n = 0; n < MAPS_K; n++) {
    uvec2 e = g_nb[k.nb + n];
    float w = uintBitsToFloat(e.y);
    if (w == 0.0) /* past the neighbours found */
      continue;
    ivec4 h = int(e.x) * (u_n_light * u_n_view * 2 * MAPS_W) + k.corner;
    vec4 c = w * k.bw;
#if MAPS_W % 2 == 0
    /* records start at even halfs: two samples a word */
    h >>= 1;
    for (int s = 0; s < MAPS_W; s += 2, h++) {
      vec2 a = unpackHalf2x16(g_rec[h.x]), b = unpackHalf2x16(g_rec[h.y]);
      vec2 d = unpackHalf2x16(g_rec[h.z]), f = unpackHalf2x16(g_rec[h.w]);
      vec2 v = c.x * a + c.y * b + c.z * d + c.w * f;
      g_re[s] += v.x;
      g_re[s + 1] += v.y;
      a = unpackHalf2x16(g_rec[h.x + MAPS_W / 2]);
      b = unpackHalf2x16(g_rec[h.y + MAPS_W / 2]);
      d = unpackHalf2x16(g_rec[h.z + MAPS_W / 2]);
      f = unpackHalf2x16(g_rec[h.w + MAPS_W / 2]);
      v = c.x * a + c.y * b + c.z * d + c.w * f;
      g_al[s] += v.x;
      g_al[s + 1] += v.y;
    }
#else
    for (int s = 0; s < MAPS_W; s++, h++) {
      g_re[s] += c.x * rec_half(h.x) + c.y * rec_half(h.y) +
                 c.z * rec_half(h.z) + c.w * rec_half(h.w);
      g_al[s] += c.x * rec_half(h.x + MAPS_W) + c.y * rec_half(h.y + MAPS_W) +
                 c.z * rec_half(h.z + MAPS_W) + c.w * rec_half(h.w + MAPS_W);
    }
#endif
  }
}

/* The blended record's reflectance and alpha at column x (lay_row's
 * maps_sample). */
vec2 column(Look k, int x) {
  vec2 col = g_col[k.bin + x];
  int s = int(col.x);
  return vec2(g_re[s] + col.y * (g_re[s + 1] - g_re[s]),
              g_al[s] + col.y * (g_al[s + 1] - g_al[s]));
}

/* maps.c: lay_row, the record of look-up k across row `at` (and the row
 * below it with `both`: a uniform HSV's), the s-map sums left 0
 * (maps_sums_cs.glsl). Its reflectance divided by alpha, times the
 * database's scale, and times the level over the row's own reflectance
 * per unit coverage where a level is given. */
void lay_row(Look k, ivec3 at, float density, bool both) {
  blend(k);
  float scale = u_re_scale;
  if (k.level > 0.0) {
    float sum_r = 0.0, sum_a = 0.0;
    for (int x = 0; x < MAPS_W; x++) {
      vec2 ra = column(k, x);
      sum_r += ra.x;
      sum_a += ra.y;
    }
    if (sum_r > 0.0 && sum_a > 1e-4 * float(MAPS_W))
      scale *= k.level / (sum_r / sum_a);
  }
  for (int x = 0; x < MAPS_W; x++, at.x++) {
    vec2 ra = column(k, x);
    vec4 t = vec4(ra.y > 1e-4 ? scale * ra.x / ra.y : 0.0, ra.y, 0.0, density);
    imageStore(u_maps, at, t);
    if (both)
      imageStore(u_maps, at + ivec3(0, 1, 0), t);
  }
}

void main() {
  MapsInst in_ = g_inst[u_first + int(gl_WorkGroupID.z)];
  int su = in_.shell.x, st = in_.shell.y, layers = in_.shell.z;
  /* HSV (i, k, j) in maps.c's order (maps_gpu.c: groups) */
  int q0 = maps_invocation();
  if (q0 >= st * layers * su)
    return;
  int j = q0 % su, k = q0 / su % layers, i = q0 / (su * layers);
  int q1 = q0 + layers * su;
  Params top = sector_params(in_.base.x + q0, in_.eye.xyz, in_.light);
  Params bot = sector_params(in_.base.x + q1, in_.eye.xyz, in_.light);
  /* eq. 6: features scaled to [0, 1], azimuths in units of pi */
  vec3 df = (top.f - bot.f) * u_fscale;
  float dv = angle_diff(top.view, bot.view) / PI;
  float dl = angle_diff(top.light, bot.light) / PI;
  float density = 0.5 * (top.f.x + bot.f.x);
  ivec3 at = ivec3(j * MAPS_W, 2 * i, in_.base.w + k);
  if (sqrt(dot(df, df) + dv * dv + dl * dl) < u_threshold) {
    /* uniform: one look-up at the averaged parameters, both rows */
    float view = top.view + 0.5 * angle_diff(top.view, bot.view);
    float light = top.light + 0.5 * angle_diff(top.light, bot.light);
    lay_row(look_at(in_.base.z + q0, view, light, in_.shell.w), at, density,
            true);
  } else { /* eq. 7: the two boundary sectors' records */
    lay_row(look_at(in_.base.y + q0, top.view, top.light, in_.shell.w), at,
            density, false);
    lay_row(look_at(in_.base.y + q1, bot.view, bot.light, in_.shell.w),
            at + ivec3(0, 1, 0), density, false);
  }
}
