/* maps_lookup.glsl - what the maps' compute shaders share of a
 * database look-up (maps_kk_cs.glsl, maps_fiber_cs.glsl): the sectors,
 * their cached neighbours, maps.c's resampling table, a sector's azimuth
 * and the database's angle cell. The renderer defines MAPS_W, MAPS_BINS,
 * MAPS_K and MAPS_SECTOR_FLOATS. */
/* maps.c's resampling table: (record sample left of the column, weight of
 * the next) for MAPS_BINS view azimuths x MAPS_W columns */
layout(std430, binding = 1) readonly buffer maps_columns { vec2 g_col[]; };
/* per sector: frame (centre P, outward N, phase direction T), its 3
 * density features and its fibre direction (zero: N x T), MAPS_SECTOR_FLOATS
 * floats */
layout(std430, binding = 3) readonly buffer maps_sectors { float g_sector[]; };
/* MAPS_K neighbours per entry (sector or HSV): (sample, weight bits),
 * weight 0 past the ones found */
layout(std430, binding = 4) readonly buffer maps_neighbors { uvec2 g_nb[]; };
const float TWO_PI = 6.28318530717958647692;
const float PI = 3.14159265358979323846;

/* maps.c: maps_azimuth */
float azimuth(int q, vec3 d) {
  int o = MAPS_SECTOR_FLOATS * q;
  vec3 n = vec3(g_sector[o + 3], g_sector[o + 4], g_sector[o + 5]);
  vec3 t = vec3(g_sector[o + 6], g_sector[o + 7], g_sector[o + 8]);
  float a = atan(dot(d, t), dot(d, n));
  return a < 0.0 ? a + TWO_PI : a;
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

uniform int u_n_view, u_n_light; /* the database's azimuths */

/* The four records around (view, light), as offsets of sample 0's
 * records of `stride` values, and their bilinear weights (hrir_db.c:
 * corners_of). */
void cell(float view, float light, int stride, out ivec4 corner,
          out vec4 bw) {
  int v0, v1, l0, l1;
  float fv, fl;
  angle_cell(view, u_n_view, v0, v1, fv);
  angle_cell(light, u_n_light, l0, l1, fl);
  bw = vec4((1.0 - fv) * (1.0 - fl), fv * (1.0 - fl), (1.0 - fv) * fl,
            fv * fl);
  corner = ivec4(l0 * u_n_view + v0, l0 * u_n_view + v1,
                 l1 * u_n_view + v0, l1 * u_n_view + v1) *
           stride;
}

/* the row of maps.c's resampling table for view azimuth `view`
 * (maps.c: maps_columns), as an offset into g_col */
int column_bin(float view) {
  float turns = view / TWO_PI;
  turns -= floor(turns);
  return (int(turns * float(MAPS_BINS) + 0.5) % MAPS_BINS) * MAPS_W;
}
