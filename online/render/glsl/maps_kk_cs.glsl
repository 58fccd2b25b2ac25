#version 430 core
/* maps_kk_cs.glsl - the paper's maps (SATF sec. 6.2: eq. 4, 6, 7, 12) of
 * the instances whose eye or light moved, written straight into their
 * textures (maps_gpu.c): what maps.c's satf_maps_update_layer and
 * satf_maps_shadow_sums make on the CPU, value for value up to float
 * rounding, in the layout of maps.h. One work group per HSV column (i, j)
 * of one instance (work group (j, i, entry)), one invocation per texel
 * column x of the HSV; the
 * layers run outer to inner, so each invocation keeps the s-map sums of
 * its two texels (eq. 12) in registers. The renderer defines MAPS_W (the
 * records' width), MAPS_BINS (maps.h: MAPS_AZIMUTH_BINS) and MAPS_K (the
 * neighbours cached per look-up). */
layout(local_size_x = MAPS_W) in;

layout(rgba16f, binding = 0) uniform writeonly image2DArray u_maps;

/* the database's records, channels 0 (reflectance) and 1 (alpha) as
 * halfs, two to a word: record (sample, view iv, light il) starts at half
 * ((sample * n_light + il) * n_view + iv) * 2 MAPS_W */
layout(std430, binding = 0) readonly buffer maps_records { uint g_rec[]; };
/* maps.c's resampling table: (record sample left of the column, weight of
 * the next) for MAPS_BINS view azimuths x MAPS_W columns */
layout(std430, binding = 1) readonly buffer maps_columns { vec2 g_col[]; };
/* per database sample: its level (maps.c: sample_re) */
layout(std430, binding = 2) readonly buffer maps_levels { float g_level[]; };
/* per sector: frame (centre P, outward N, phase direction T) and its 3
 * density features, 12 floats */
layout(std430, binding = 3) readonly buffer maps_sectors { float g_sector[]; };
/* MAPS_K neighbours per entry (sector or HSV): (sample, weight bits),
 * weight 0 past the ones found */
layout(std430, binding = 4) readonly buffer maps_neighbors { uvec2 g_nb[]; };
/* per instance built: eye (xyz), light (xyzw: w 0 direction, 1 position)
 * in its frame; first sector, first sector neighbours, first HSV
 * neighbours, first texture layer; su, st, layers, orientation_free */
struct MapsInst {
  vec4 eye, light;
  ivec4 base, shell;
};
layout(std430, binding = 5) readonly buffer maps_insts { MapsInst g_inst[]; };

uniform int u_first;        /* this dispatch's first entry of g_inst */
uniform int u_n_view, u_n_light;
uniform float u_re_scale;   /* maps.c: reflectance_scale */
uniform vec3 u_fscale;      /* 1 / each feature's range over the database */
uniform float u_threshold;  /* eq. 6 */

const float TWO_PI = 6.28318530717958647692;
const float PI = 3.14159265358979323846;

shared float s_sum[4][MAPS_W];

/* maps.c: maps_azimuth */
float azimuth(int q, vec3 d) {
  int o = 12 * q;
  vec3 n = vec3(g_sector[o + 3], g_sector[o + 4], g_sector[o + 5]);
  vec3 t = vec3(g_sector[o + 6], g_sector[o + 7], g_sector[o + 8]);
  float a = atan(dot(d, t), dot(d, n));
  return a < 0.0 ? a + TWO_PI : a;
}

struct Params {
  vec3 f;
  float view, light;
};

Params sector_params(int q, vec3 eye, vec4 light) {
  int o = 12 * q;
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

/* hrir_db.c: angle_cell (in double, as there) */
void angle_cell(float theta, int n, out int i0, out int i1, out float f) {
  double x = double(theta) / 6.283185307179586LF * double(n);
  if (!(x >= 0.0LF && x < double(n)))
    x -= floor(x / double(n)) * double(n);
  double r = floor(x + 0.5LF);
  if (abs(x - r) < 1e-4LF)
    x = r;
  int i = int(floor(x));
  f = float(x - double(i));
  i0 = i >= n ? i - n : i;
  i1 = i0 + 1 == n ? 0 : i0 + 1;
}

float rec_half(int h) {
  uint w = g_rec[h >> 1];
  return unpackHalf2x16((h & 1) == 0 ? w : w >> 16).x;
}

/* A record's reflectance at samples s and s + 1, then its alpha there,
 * from the record's sample s at half h. */
vec4 samples4(int h) {
  return vec4(rec_half(h), rec_half(h + 1), rec_half(h + MAPS_W),
              rec_half(h + MAPS_W + 1));
}

/* One look-up (eq. 4: satf_db_lookup_cell_range's blend, neighbour by
 * neighbour, corner by corner) of a record at (view, light) from the
 * neighbours at entry nb, read where lay_row reads it: reflectance and
 * alpha at the column of this invocation (x) as seen from `view`; *level:
 * the neighbours' blended level (orientation-free), else 0. */
vec2 lookup(int nb, float view, float light, int x, int free_level,
            out float level) {
  int v0, v1, l0, l1;
  float fv, fl;
  angle_cell(view, u_n_view, v0, v1, fv);
  angle_cell(light, u_n_light, l0, l1, fl);
  /* the four corners' weights and records (vectors, not arrays: a
   * rasteriser on the CPU keeps an indexed array in memory) */
  vec4 bw = vec4((1.0 - fv) * (1.0 - fl), fv * (1.0 - fl), (1.0 - fv) * fl,
                 fv * fl);
  ivec4 corner = ivec4(l0 * u_n_view + v0, l0 * u_n_view + v1,
                       l1 * u_n_view + v0, l1 * u_n_view + v1);
  /* maps.c: maps_columns */
  float turns = view / TWO_PI;
  turns -= floor(turns);
  int b = int(turns * float(MAPS_BINS) + 0.5) % MAPS_BINS;
  vec2 col = g_col[b * MAPS_W + x];
  int s = int(col.x);
  vec4 acc = vec4(0.0); /* re[s], re[s + 1], al[s], al[s + 1] */
  float l = 0.0, wsum = 0.0;
  for (int n = 0; n < MAPS_K; n++) {
    uvec2 e = g_nb[nb * MAPS_K + n];
    float w = uintBitsToFloat(e.y);
    if (w == 0.0)
      continue;
    ivec4 h = ((int(e.x) * u_n_light * u_n_view + corner) * 2 * MAPS_W) + s;
    vec4 wc = w * bw;
    acc += wc.x * samples4(h.x) + wc.y * samples4(h.y) +
           wc.z * samples4(h.z) + wc.w * samples4(h.w);
    float sre = g_level[e.x];
    if (sre > 0.0) {
      l += w * sre;
      wsum += w;
    }
  }
  level = free_level != 0 && wsum > 0.0 ? l / wsum : 0.0;
  return vec2(acc.x + col.y * (acc.y - acc.x), acc.z + col.y * (acc.w - acc.z));
}

/* maps.c: lay_row's scale, from the row's sums over its columns */
float row_scale(float level, float sum_r, float sum_a) {
  float scale = u_re_scale;
  if (level > 0.0 && sum_r > 0.0 && sum_a > 1e-4 * float(MAPS_W))
    scale *= level / (sum_r / sum_a);
  return scale;
}

vec4 texel(vec2 ra, float scale, float sums, float density) {
  return vec4(ra.y > 1e-4 ? scale * ra.x / ra.y : 0.0, ra.y, sums, density);
}

void main() {
  MapsInst in_ = g_inst[u_first + int(gl_WorkGroupID.z)];
  int su = in_.shell.x, st = in_.shell.y, layers = in_.shell.z;
  int i = int(gl_WorkGroupID.y), j = int(gl_WorkGroupID.x);
  int x = int(gl_LocalInvocationID.x);
  float sum0 = 0.0, sum1 = 0.0; /* eq. 12 at this column's two texels */
  for (int k = layers - 1; k >= 0; k--) {
    int q0 = (i * layers + k) * su + j, q1 = q0 + layers * su;
    Params top = sector_params(in_.base.x + q0, in_.eye.xyz, in_.light);
    Params bot = sector_params(in_.base.x + q1, in_.eye.xyz, in_.light);
    /* eq. 6: features scaled to [0, 1], azimuths in units of pi */
    vec3 df = (top.f - bot.f) * u_fscale;
    float dv = angle_diff(top.view, bot.view) / PI;
    float dl = angle_diff(top.light, bot.light) / PI;
    bool uniform_hsv = sqrt(dot(df, df) + dv * dv + dl * dl) < u_threshold;
    float density = 0.5 * (top.f.x + bot.f.x);
    vec2 a, c;
    float la, lc;
    if (uniform_hsv) { /* one look-up at the averaged parameters */
      float view = top.view + 0.5 * angle_diff(top.view, bot.view);
      float light = top.light + 0.5 * angle_diff(top.light, bot.light);
      a = lookup(in_.base.z + q0, view, light, x, in_.shell.w, la);
      c = a;
      lc = la;
    } else { /* eq. 7: the two boundary sectors' records */
      a = lookup(in_.base.y + q0, top.view, top.light, x, in_.shell.w, la);
      c = lookup(in_.base.y + q1, bot.view, bot.light, x, in_.shell.w, lc);
    }
    /* the rows' sums, which only the orientation-free level reads (the
     * same for the whole work group: the barriers stay in uniform flow) */
    vec4 sums = vec4(0.0);
    if (in_.shell.w != 0) {
      s_sum[0][x] = a.x;
      s_sum[1][x] = a.y;
      s_sum[2][x] = c.x;
      s_sum[3][x] = c.y;
      barrier();
      for (int y = 0; y < MAPS_W; y++)
        sums += vec4(s_sum[0][y], s_sum[1][y], s_sum[2][y], s_sum[3][y]);
      barrier(); /* read before the next layer writes */
    }
    ivec3 at = ivec3(j * MAPS_W + x, 2 * i, in_.base.w + k);
    imageStore(u_maps, at,
               texel(a, row_scale(la, sums.x, sums.y), sum0, density));
    at.y++;
    imageStore(u_maps, at,
               texel(c, row_scale(lc, sums.z, sums.w), sum1, density));
    sum0 += a.y;
    sum1 += c.y;
  }
}
