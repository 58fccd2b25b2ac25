#version 430 core
/* maps_fiber_cs.glsl - the physical mode's maps (maps_fiber.h) of the
 * instances whose eye or lights moved, written straight into their
 * RGBA32UI textures (maps_gpu.c): what maps_fiber.c's
 * satf_maps_fiber_build makes on the CPU, value for value up to float
 * rounding, the s-map sums of eq. 12 left to maps_sums_cs.glsl. One
 * invocation per boundary sector (i, k, j), i in [0, st], of one instance
 * (work group z: the instance's entry), which lays its row across rows
 * 2i - 1 and 2i (SATF eq. 7: HSV i shows boundaries i and i + 1). Per
 * light: M_p of d'Eon 2011 eq. 7 at the sector's view and light
 * inclinations (maps_fiber.c's table), the lobes of the records summed
 * with it, E (M_R R + M_TT TT + M_TRT TRT + M_MS MS); the key light's
 * records blended from every cached neighbour (SATF eq. 4), the others'
 * from the nearest alone, as on the CPU. The renderer defines MAPS_W,
 * MAPS_BINS, MAPS_K, FIBER_CH (the database's channels), FIBER_LEVELS,
 * FIBER_LEVEL_OF (each colour's absorption level), MP_SIZE, REL_BINS and
 * REL_STRIDE (maps_fiber.h: maps_fiber_tables); MAPS_W is even. */
layout(local_size_x = 64) in;

layout(rgba32ui, binding = 0) uniform writeonly uimage2DArray u_maps;

/* the re-levelled database's records as halfs, two to a word (MAPS_W is
 * even, so a record's channels start at even halfs), every channel:
 * record (sample, view iv, light il) starts at half ((sample * n_light +
 * il) * n_view + iv) * FIBER_CH * MAPS_W, channel c at c * MAPS_W of it
 * (satf/db.h) */
layout(std430, binding = 0) readonly buffer fiber_records { uint g_rec[]; };
#include "maps_inst.glsl"
#include "maps_lookup.glsl"
/* per instance entry, SATF_MAX_LIGHTS lights of two vec4s: the light in
 * the instance's frame (as MapsInst.light) and its RGB irradiance */
layout(std430, binding = 6) readonly buffer fiber_lights { vec4 g_light[]; };
/* M_p's table, MP_SIZE^2 nodes of the 4 lobes (maps_fiber.c: mp_tables) */
layout(std430, binding = 7) readonly buffer fiber_mp { vec4 g_mp[]; };
/* the orientation-free levels (maps_fiber.c: rel_levels) */
layout(std430, binding = 8) readonly buffer fiber_rel { float g_rel[]; };

uniform int u_n_lights; /* the scene's lights, the key light first */
uniform int u_trt;      /* 0: no TRT lobe (Fig. 4b's switch) */

const ivec3 LEVEL_OF = FIBER_LEVEL_OF;

/* the sector's frame and its fibre direction (maps.h: hair) */
vec3 g_p, g_hair;
int g_q;

/* maps_fiber.c: sector_direction, the azimuth in the sector's plane and
 * the sine of the inclination to the hair */
vec2 direction(vec3 d) {
  float len = sqrt(dot(d, d));
  float s = len > 0.0 ? dot(d, g_hair) / len : 0.0;
  return vec2(azimuth(g_q, d), clamp(s, -1.0, 1.0));
}

/* maps_fiber.c: mp_lookup, the four lobes' M_p, bilinear in the table */
vec4 mp_lookup(float si, float so) {
  float x = (si + 1.0) * 0.5 * float(MP_SIZE - 1);
  float y = (so + 1.0) * 0.5 * float(MP_SIZE - 1);
  int a = clamp(int(x), 0, MP_SIZE - 2), b = clamp(int(y), 0, MP_SIZE - 2);
  float fx = x - float(a), fy = y - float(b);
  int t = b * MP_SIZE + a;
  vec4 lo = g_mp[t] + fx * (g_mp[t + 1] - g_mp[t]);
  vec4 hi = g_mp[t + MP_SIZE] + fx * (g_mp[t + MP_SIZE + 1] - g_mp[t + MP_SIZE]);
  return lo + fy * (hi - lo);
}

/* record samples x and x + 1 at half h (even) */
vec2 rec2(int h) { return unpackHalf2x16(g_rec[h >> 1]); }

/* Per colour, the lobes at M_p mp of record samples x and x + 1, R's at
 * half o (even), then TT, TRT and MS per absorption level
 * (SATF_DB_CH_*), MAPS_W apart: sample x's in a, x + 1's in b. */
void lobes(int o, vec4 mp, out vec3 a, out vec3 b) {
  ivec3 tt = o + (1 + LEVEL_OF) * MAPS_W;
  ivec3 tr = tt + FIBER_LEVELS * MAPS_W, ms = tr + FIBER_LEVELS * MAPS_W;
  vec2 r = rec2(o);
  vec2 t0 = rec2(tt.x), t1 = rec2(tt.y), t2 = rec2(tt.z);
  vec2 u0 = rec2(tr.x), u1 = rec2(tr.y), u2 = rec2(tr.z);
  vec2 m0 = rec2(ms.x), m1 = rec2(ms.y), m2 = rec2(ms.z);
  a = mp.x * r.x + mp.y * vec3(t0.x, t1.x, t2.x) +
      mp.z * vec3(u0.x, u1.x, u2.x) + mp.w * vec3(m0.x, m1.x, m2.x);
  b = mp.x * r.y + mp.y * vec3(t0.y, t1.y, t2.y) +
      mp.z * vec3(u0.y, u1.y, u2.y) + mp.w * vec3(m0.y, m1.y, m2.y);
}

/* the same over a sample's orientation-free levels (stride 1) */
vec3 rel_lobes(int o, vec4 mp) {
  ivec3 tt = o + 1 + LEVEL_OF;
  ivec3 tr = tt + FIBER_LEVELS, ms = tr + FIBER_LEVELS;
  return mp.x * g_rel[o] + mp.y * vec3(g_rel[tt.x], g_rel[tt.y], g_rel[tt.z]) +
         mp.z * vec3(g_rel[tr.x], g_rel[tr.y], g_rel[tr.z]) +
         mp.w * vec3(g_rel[ms.x], g_rel[ms.y], g_rel[ms.z]);
}

/* per record sample: the key light's lobes (rgb, still premultiplied by
 * coverage) and alpha; a fill light's lobes; the fill lights' sum */
vec4 g_key[MAPS_W];
vec3 g_row[MAPS_W], g_fill[MAPS_W];

/* The key light's records blended over the neighbours at nb (SATF eq.
 * 4), their lobes at M_p mp and alpha into g_key. */
void blend_key(int nb, ivec4 corner, vec4 bw, vec4 mp) {
  for (int x = 0; x < MAPS_W; x++)
    g_key[x] = vec4(0.0);
  for (int n = 0; n < MAPS_K; n++) {
    uvec2 e = g_nb[nb + n];
    float w = uintBitsToFloat(e.y);
    if (w == 0.0) /* past the neighbours found */
      continue;
    int s0 = int(e.x) * (u_n_light * u_n_view * FIBER_CH * MAPS_W);
    for (int c = 0; c < 4; c++) {
      int o = s0 + corner[c];
      float wc = w * bw[c];
      for (int x = 0; x < MAPS_W; x += 2) {
        vec3 a, b;
        lobes(o + 2 * MAPS_W + x, mp, a, b);
        vec2 al = rec2(o + MAPS_W + x);
        g_key[x] += wc * vec4(a, al.x);
        g_key[x + 1] += wc * vec4(b, al.y);
      }
    }
  }
}

/* A fill light's records from the nearest neighbour, sample s, their lobes
 * at M_p mp into g_row. */
void blend_fill(int s, ivec4 corner, vec4 bw, vec4 mp) {
  int s0 = s * (u_n_light * u_n_view * FIBER_CH * MAPS_W);
  for (int x = 0; x < MAPS_W; x += 2) {
    vec3 va = vec3(0.0), vb = vec3(0.0);
    for (int c = 0; c < 4; c++) {
      vec3 a, b;
      lobes(s0 + corner[c] + 2 * MAPS_W + x, mp, a, b);
      va += bw[c] * a;
      vb += bw[c] * b;
    }
    g_row[x] = va;
    g_row[x + 1] = vb;
  }
}

/* maps_fiber.c: level_scale with rel_level, per colour what turns a
 * light's row (radiance `sum` over its columns' coverage `sum_a`) into
 * its samples' orientation-free level at view minus light azimuth, the
 * neighbours at nb (only the first with `nearest`); 1 where none has
 * coverage or radiance. */
vec3 level_scale(int nb, bool nearest, float view, float light, vec4 mp,
                 vec3 sum, float sum_a) {
  float rel = (view - light) / TWO_PI;
  float pos = (rel - floor(rel)) * float(REL_BINS);
  int b0 = int(pos);
  float t = pos - float(b0);
  b0 %= REL_BINS;
  int bins[2] = int[2](b0, (b0 + 1) % REL_BINS);
  float bw[2] = float[2](1.0 - t, t);
  vec3 level = vec3(0.0);
  float wsum = 0.0;
  for (int n = 0; n < (nearest ? 1 : MAPS_K); n++) {
    uvec2 e = g_nb[nb + n];
    float w = nearest ? 1.0 : uintBitsToFloat(e.y);
    for (int b = 0; b < 2; b++) {
      int o = (int(e.x) * REL_BINS + bins[b]) * REL_STRIDE;
      float ww = w * bw[b];
      if (g_rel[o] <= 0.0 || ww <= 0.0)
        continue;
      level += ww * rel_lobes(o + 1, mp);
      wsum += ww;
    }
  }
  vec3 one = vec3(1.0);
  if (wsum <= 0.0 || sum_a <= 1e-4 * float(MAPS_W))
    return one;
  level /= wsum;
  vec3 own = sum / sum_a;
  for (int c = 0; c < 3; c++)
    if (own[c] > 0.0 && level[c] > 0.0)
      one[c] = level[c] / own[c];
  return one;
}

/* maps_fiber.c: mp_tilted, M_p over TILT_TANGENTS fibre tangents on the
 * cone at `tilt` to the hair (u, v: unit axes across it, maps_fiber.c
 * cone_at; le, ve:
 * unit directions to the light and the eye), each tangent weighted by its
 * width seen from the eye */
const int TILT_TANGENTS = 8;
vec4 mp_tilted(vec3 le, vec3 ve, vec3 u, vec3 v, float tilt) {
  vec4 sum = vec4(0.0);
  float wsum = 0.0;
  for (int k = 0; k < TILT_TANGENTS; k++) {
    float psi = 6.2831853 * (float(k) + 0.5) / float(TILT_TANGENTS);
    vec3 t = cos(tilt) * g_hair + sin(tilt) * (cos(psi) * u + sin(psi) * v);
    float so = dot(ve, t);
    float wo = sqrt(max(1.0 - so * so, 0.0));
    sum += wo * mp_lookup(dot(le, t), so);
    wsum += wo;
  }
  return wsum > 0.0 ? sum / wsum : sum;
}

/* The row's key light (g_key.rgb) or fill light (g_row) and the key's
 * alpha summed over the row's columns, each resampled to the view (bin:
 * column_bin), as lay_fiber_row lays them. */
vec4 row_sums(int bin, bool key) {
  vec4 s = vec4(0.0);
  for (int x = 0; x < MAPS_W; x++) {
    vec2 col = g_col[bin + x];
    int i = int(col.x);
    vec3 r0 = key ? g_key[i].rgb : g_row[i];
    vec3 r1 = key ? g_key[i + 1].rgb : g_row[i + 1];
    s += vec4(r0 + col.y * (r1 - r0),
              g_key[i].a + col.y * (g_key[i + 1].a - g_key[i].a));
  }
  return s;
}

void main() {
  MapsInst in_ = g_inst[u_first + int(gl_WorkGroupID.z)];
  int su = in_.shell.x, st = in_.shell.y, layers = in_.shell.z;
  /* boundary sector (i, k, j) in maps.c's order */
  int q0 = maps_invocation();
  if (q0 >= (st + 1) * layers * su)
    return;
  int j = q0 % su, k = q0 / su % layers, i = q0 / (su * layers);
  g_q = in_.base.x + q0;
  int o = MAPS_SECTOR_FLOATS * g_q;
  g_p = vec3(g_sector[o], g_sector[o + 1], g_sector[o + 2]);
  vec3 axis_u = vec3(g_sector[o + 3], g_sector[o + 4], g_sector[o + 5]);
  vec3 axis_v = vec3(g_sector[o + 6], g_sector[o + 7], g_sector[o + 8]);
  /* the fibres' own course where the strands gave it (maps.h: hair) */
  vec3 own = vec3(g_sector[o + 12], g_sector[o + 13], g_sector[o + 14]);
  g_hair = dot(own, own) > 0.0 ? own : normalize(cross(axis_u, axis_v));
  /* across the hair within the surface: T, or hair x N where the strands
   * turned the hair (maps_fiber.c: cone_at) */
  vec3 across =
      dot(own, own) > 0.0 ? normalize(cross(g_hair, axis_u)) : normalize(axis_v);
  vec2 view = direction(in_.eye.xyz - g_p);
  float tilt = in_.eye.w; /* the density's curl, radians (maps_gpu.c) */
  int nb = (in_.base.y + q0) * MAPS_K;
  int bin = column_bin(view.x);
  int lights = (u_first + int(gl_WorkGroupID.z)) * SATF_MAX_LIGHTS * 2;
  for (int x = 0; x < MAPS_W; x++)
    g_fill[x] = vec3(0.0);
  for (int li = 0; li < u_n_lights; li++) {
    vec4 L = g_light[lights + 2 * li];
    vec3 ld = L.xyz - L.w * g_p;
    vec3 e = g_light[lights + 2 * li + 1].rgb;
    if (L.w > 0.0) /* a point light's falloff */
      e *= 1.0 / max(dot(ld, ld), 1e-6);
    vec2 light = direction(ld);
    vec4 mp = tilt > 0.0
                  ? mp_tilted(normalize(ld), normalize(in_.eye.xyz - g_p),
                              normalize(axis_u), across, tilt)
                  : mp_lookup(light.y, view.y);
    if (u_trt == 0)
      mp.z = 0.0;
    ivec4 corner;
    vec4 bw;
    cell(view.x, light.x, FIBER_CH * MAPS_W, corner, bw);
    if (li == 0)
      blend_key(nb, corner, bw, mp);
    else
      blend_fill(int(g_nb[nb].x), corner, bw, mp);
    if (in_.shell.w != 0) { /* the orientation-free level */
      vec4 s = row_sums(bin, li == 0);
      e *= level_scale(nb, li > 0, view.x, light.x, mp, s.rgb, s.a);
    }
    for (int x = 0; x < MAPS_W; x++)
      if (li == 0)
        g_key[x].rgb *= e;
      else
        g_fill[x] += e * g_row[x];
  }
  /* maps_fiber.c: lay_fiber_row, resampled to the view, divided by alpha
   * (eq. 14 multiplies by it again); the s-map sum follows */
  ivec3 at = ivec3(j * MAPS_W, 2 * i, in_.base.w + k);
  for (int x = 0; x < MAPS_W; x++, at.x++) {
    vec2 col = g_col[bin + x];
    int s = int(col.x);
    vec4 tk = g_key[s] + col.y * (g_key[s + 1] - g_key[s]);
    vec3 tf = g_fill[s] + col.y * (g_fill[s + 1] - g_fill[s]);
    float inv = tk.a > 1e-4 ? 1.0 / tk.a : 0.0;
    tk.rgb *= inv;
    tf *= inv;
    uvec4 t = uvec4(packHalf2x16(tk.rg), packHalf2x16(tk.ba),
                    packHalf2x16(tf.rg), packHalf2x16(vec2(tf.b, 0.0)));
    if (i > 0)
      imageStore(u_maps, at - ivec3(0, 1, 0), t);
    if (i < st)
      imageStore(u_maps, at, t);
  }
}
