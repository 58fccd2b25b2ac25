/* maps_fiber.c - see maps_fiber.h: the maps of the physical shading mode,
 * from a fibre database (format version 2, satf/db.h) and the fibre model
 * (satf/fiber.h). */
#include "maps_fiber.h"

#include "fiber_gpu.h"
#include "half.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "satf/fiber.h"
#include "satf/math.h"

/* M_p tabulated over (sin theta_i, sin theta_o) in [-1, 1]^2: the maps
 * evaluate it four times per light and sector, each a Bessel function and
 * exponentials; bilinear in a 256 x 256 table it takes about a quarter
 * off the map stage (measured on cluster_6a). */
#define MP_TABLE SATF_FIBER_MP_NODES

/* Four floats in one vector (GCC's and clang's vector extension): a
 * texel's channels, a sample's colours and alpha, or the four lobes' M_p
 * at one table node. */
typedef float v4f __attribute__((vector_size(16)));

struct satf_maps_fiber {
  /* MP_TABLE^2 nodes of 4 lobes (R, TT, TRT with their tilts, MS), the
   * lobes of a node side by side: a look-up reads 2 x 32 bytes where four
   * separate tables (1 MB in all) cost four cache misses a light and
   * sector (perf, hair_7c: the hottest loads of the map code) */
  v4f *mp;
  satf_db *db;     /* the fibre database re-levelled at the hair's sigma_a */
  int levels;      /* its absorption levels (distinct RGB values) */
  int level_of[3]; /* the level of each colour channel */
  satf_fiber fiber;
  float v_ms;   /* the longitudinal variance of multiple scattering */
  int channels; /* the database's (satf_db_channels) */
  /* per sample and relative azimuth bin (view minus light, rel_bins over
   * the full circle): its records' mean alpha, then each lobe channel
   * (SATF_DB_CH_R on) per unit coverage, over the sector orientations
   * seen from outside (rel_levels) */
  float *rel;
  int rel_bins;
};

/* Floats per (sample, bin) of satf_maps_fiber.rel: alpha and the lobes of
 * a database of `channels` channels. */
static int rel_stride_of(int channels) { return 1 + channels - SATF_DB_CH_R; }
static int rel_stride(const satf_maps_fiber *f) {
  return rel_stride_of(f->channels);
}

/* Whether azimuth i of n (2 pi i / n from the sector's outward normal,
 * trace.h) lies on the outer side of the sector (as maps.c's front). */
static int front(int i, int n) { return 4 * i < n || 4 * i > 3 * n; }

/* The orientation-free levels of the physical records (maps.h:
 * satf_map_options.orientation_free; maps.c does the same for Phong
 * records). As a sector turns round its cluster, its view and light
 * azimuths turn together: what stays is their difference, which sets how
 * the fibre lobes mix (a back-lit sector's TT, a front-lit one's R). So a
 * sample's level is kept per difference, averaged over the orientations
 * whose view lies on the sector's outer side (the light anywhere: a
 * back light reaches the front sectors from inside, through the hair). */
static satf_status rel_levels(satf_maps_fiber *f, satf_error *err) {
  const satf_build_params *p = satf_db_params(f->db);
  int nb = p->n_view, st = rel_stride(f), w = p->trace.width;
  f->rel_bins = nb;
  f->rel = calloc((size_t)p->samples * (size_t)nb * (size_t)st, sizeof *f->rel);
  double *sum = malloc((size_t)nb * (size_t)st * sizeof *sum);
  int *count = malloc((size_t)nb * sizeof *count);
  if (!f->rel || !sum || !count) {
    free(sum);
    free(count);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot allocate the fibre records' levels");
  }
  for (int s = 0; s < p->samples; s++) {
    memset(sum, 0, (size_t)nb * (size_t)st * sizeof *sum);
    memset(count, 0, (size_t)nb * sizeof *count);
    for (int iv = 0; iv < p->n_view; iv++) {
      if (!front(iv, p->n_view))
        continue;
      for (int il = 0; il < p->n_light; il++) {
        double rel = (double)iv / p->n_view - (double)il / p->n_light;
        int b = (int)lround((rel - floor(rel)) * nb) % nb;
        const float *rec = satf_db_record_channels(f->db, s, iv, il);
        double *d = sum + (size_t)b * st;
        for (int c = 0; c < st; c++) { /* SATF_DB_CH_ALPHA on */
          const float *ch = rec + (size_t)(SATF_DB_CH_ALPHA + c) * w;
          double t = 0.0;
          for (int x = 0; x < w; x++)
            t += ch[x];
          d[c] += t;
        }
        count[b]++;
      }
    }
    float *out = f->rel + (size_t)s * nb * st;
    for (int b = 0; b < nb; b++) {
      const double *d = sum + (size_t)b * st;
      if (count[b] == 0 || d[0] <= 1e-3 * count[b])
        continue; /* no coverage: no level (alpha 0) */
      out[b * st] = (float)(d[0] / (count[b] * (double)w));
      for (int c = 1; c < st; c++)
        out[b * st + c] = (float)(d[c] / d[0]);
    }
  }
  free(sum);
  free(count);
  return SATF_OK;
}

/* The hair's RGB absorption as strictly ascending levels, and the level of
 * each colour (equal values share one). */
static int rgb_levels(const float sigma[3], float *levels, int level_of[3]) {
  int order[3] = {0, 1, 2};
  for (int a = 0; a < 3; a++)
    for (int b = a + 1; b < 3; b++)
      if (sigma[order[b]] < sigma[order[a]]) {
        int t = order[a];
        order[a] = order[b];
        order[b] = t;
      }
  int n = 0;
  for (int a = 0; a < 3; a++) {
    float s = sigma[order[a]];
    if (n == 0 || s > levels[n - 1])
      levels[n++] = s;
    level_of[order[a]] = n - 1;
  }
  return n;
}

static void mp_tables(satf_maps_fiber *f) {
  satf_fiber_mp_table(&f->fiber, f->v_ms, MP_TABLE, (float *)f->mp);
}

/* The four lobes' M_p at (sin theta_i, sin theta_o), bilinear (each lane
 * the scalar interpolation of its lobe, in its order). */
static v4f mp_lookup(const satf_maps_fiber *f, float si, float so) {
  float x = (si + 1.0f) * 0.5f * (MP_TABLE - 1);
  float y = (so + 1.0f) * 0.5f * (MP_TABLE - 1);
  int a = (int)x, b = (int)y;
  a = a < 0 ? 0 : a > MP_TABLE - 2 ? MP_TABLE - 2 : a;
  b = b < 0 ? 0 : b > MP_TABLE - 2 ? MP_TABLE - 2 : b;
  float fx = x - (float)a, fy = y - (float)b;
  const v4f *t = f->mp + (size_t)b * MP_TABLE + (size_t)a;
  v4f lo = t[0] + fx * (t[1] - t[0]);
  v4f hi = t[MP_TABLE] + fx * (t[MP_TABLE + 1] - t[MP_TABLE]);
  return lo + fy * (hi - lo);
}

satf_status satf_maps_fiber_create(const satf_db *db,
                                   const satf_scene_material *mat, int threads,
                                   satf_maps_fiber **out, satf_error *err) {
  *out = NULL;
  if (satf_db_kind(db) != SATF_RECORD_FIBER)
    return satf_error_set(
        err, SATF_ERR_INCOMPATIBLE,
        "the physical shading mode needs a fibre database (format version "
        "2: satf-build --kind fiber); this one holds Phong records");
  satf_maps_fiber *f = calloc(1, sizeof *f);
  if (!f)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  fiber_from_material(mat, &f->fiber);
  const float *sigma = f->fiber.sigma_a;
  /* Our choice (papers 003/004 model single scattering only): light
   * scattered at two or more fibres has gone through at least a TT and
   * another lobe, so its longitudinal spread is about the sum of theirs;
   * we take v_TT + v_TRT, unshifted (the lobes' shifts partly cancel). */
  f->v_ms = f->fiber.v[1] + f->fiber.v[2];
  if (!(f->mp = malloc(MP_TABLE * MP_TABLE * sizeof *f->mp))) {
    free(f);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  mp_tables(f);
  float levels[3];
  f->levels = rgb_levels(sigma, levels, f->level_of);
  satf_status st = satf_db_relevel(db, levels, f->levels, threads, &f->db, err);
  if (st != SATF_OK) {
    free(f->mp);
    free(f);
    return st;
  }
  f->channels = satf_db_channels(f->db);
  st = rel_levels(f, err);
  if (st != SATF_OK) {
    satf_maps_fiber_destroy(f);
    return st;
  }
  *out = f;
  return SATF_OK;
}

void maps_fiber_lights(const view *v, const float inv[16],
                       satf_fiber_light *lights) {
  float col[3 * SATF_SCENE_MAX_LIGHTS];
  view_light_colors(v, col);
  for (int l = 0; l < v->nlights; l++) {
    view_light_local(inv, &v->lights[l], lights[l].local);
    memcpy(lights[l].rgb, col + 3 * l, sizeof lights[l].rgb);
  }
}

void maps_fiber_tables_get(const satf_maps_fiber *f, maps_fiber_tables *t) {
  t->db = f->db;
  t->mp = (const float *)f->mp;
  t->mp_size = MP_TABLE;
  t->rel = f->rel;
  t->rel_bins = f->rel_bins;
  t->rel_stride = rel_stride(f);
  t->levels = f->levels;
  memcpy(t->level_of, f->level_of, sizeof t->level_of);
}

void maps_fiber_shape_of(const satf_db *db, const satf_scene_material *mat,
                         maps_fiber_shape *out) {
  satf_fiber fiber;
  fiber_from_material(mat, &fiber);
  float levels[3];
  int level_of[3];
  out->levels = rgb_levels(fiber.sigma_a, levels, level_of);
  /* satf_db_relevel's copy, as satf_maps_fiber_create asks for it */
  out->channels = SATF_DB_FIBER_CHANNELS(out->levels);
  out->mp_size = MP_TABLE;
  out->rel_bins = satf_db_params(db)->n_view; /* as rel_levels */
  out->rel_stride = rel_stride_of(out->channels);
}

void satf_maps_fiber_destroy(satf_maps_fiber *f) {
  if (f) {
    free(f->mp);
    free(f->rel);
    satf_db_destroy(f->db);
    free(f);
  }
}

/* One direction seen from a sector: its azimuth in the sector's plane and
 * its longitudinal angle to the hair (sin, cos), pbrt's theta. */
typedef struct direction {
  float azimuth, sin_t, cos_t;
} direction;

static direction sector_direction(const float *frame, const float hair[3],
                                  const float d[3]) {
  direction r;
  float len = sqrtf(satf_dot3f(d, d));
  float s = len > 0.0f ? satf_dot3f(d, hair) / len : 0.0f;
  s = s > 1.0f ? 1.0f : s < -1.0f ? -1.0f : s;
  r.azimuth = maps_azimuth(frame, d);
  r.sin_t = s;
  r.cos_t = sqrtf(1.0f - s * s);
  return r;
}

/* What boundary sector i of a column sees of the lights, for every layer
 * of the column: a directional light's direction and inclination depend
 * only on the sector's axes (frame + 3, frame + 6) and fibre direction,
 * which in a generalized cylinder are those of its (i, j) in every layer
 * (satf_shell_geom_create: the section's normal plane at u;
 * satf_sector_hair_directions). Kept with the axes and direction they were
 * found at and used again only for bit-identical ones, so the sector's own
 * computation would give the same values; they cost two atan2s and a
 * square root a light and sector (with the view's, about 9% of the CPU
 * samples of hair_7c's physical frames, perf). */
typedef struct column_entry {
  float axes[6];
  int ready;     /* axes, hair and light are set */
  float hair[3]; /* maps_sector_hair: along t, root to tip */
  direction light[SATF_SCENE_MAX_LIGHTS];
} column_entry;

/* cos and sin of the tangents' azimuths about the hair, 2 pi (k + 1/2) / 8 */
static const float TILT_CS[TILT_TANGENTS][2] = {
    {0.92387953f, 0.38268343f},   {0.38268343f, 0.92387953f},
    {-0.38268343f, 0.92387953f},  {-0.92387953f, 0.38268343f},
    {-0.92387953f, -0.38268343f}, {-0.38268343f, -0.92387953f},
    {0.38268343f, -0.92387953f},  {0.92387953f, -0.38268343f}};

/* What sector q sees of the eye and every light, found once: the look-up
 * one sector ahead fetches the key light's records by them, and the
 * sector's own look-up then uses them. */
typedef struct sector_look {
  size_t q;
  float hair[3];
  direction view;
  direction light[SATF_SCENE_MAX_LIGHTS];
  float fall[SATF_SCENE_MAX_LIGHTS]; /* falloff (1: directional) */
  satf_db_cell key; /* the key light's look-up's, for it and its prefetch */
  /* with a tilt (satf_map_options.tilt) only: the fibre tangents on its
   * cone, each one's sin theta to the eye and its width seen from the eye
   * over their sum, and the unit directions to the lights */
  float tangent[TILT_TANGENTS][3], sin_eye[TILT_TANGENTS], width[TILT_TANGENTS],
      to_light[SATF_SCENE_MAX_LIGHTS][3];
} sector_look;

/* Light l from sector frame fr: its direction and falloff. */
static direction light_direction(const float *fr, const float hair[3],
                                 const satf_fiber_light *l, float *fall) {
  const float *L = l->local;
  float ld[3] = {L[0] - L[3] * fr[0], L[1] - L[3] * fr[1], L[2] - L[3] * fr[2]};
  *fall = L[3] > 0.0f ? 1.0f / fmaxf(satf_dot3f(ld, ld), 1e-6f) : 1.0f;
  return sector_direction(fr, hair, ld);
}

/* The unit vector from sector frame fr towards light l. */
static void light_vector(const float *fr, const satf_fiber_light *l,
                         float out[3]) {
  const float *L = l->local;
  for (int c = 0; c < 3; c++)
    out[c] = L[c] - L[3] * fr[c];
  satf_normalize3f(out);
}

void maps_cone_tangents(const float hair[3], const float *frame, int own,
                        float tilt, float tangent[TILT_TANGENTS][3]) {
  float u[3], v[3], ct = cosf(tilt), st = sinf(tilt);
  memcpy(u, frame + 3, sizeof u);
  if (own) /* the strands turned the hair within the surface: T no longer
              lies across it */
    satf_cross3f(hair, frame + 3, v);
  else
    memcpy(v, frame + 6, sizeof v);
  satf_normalize3f(u);
  satf_normalize3f(v);
  for (int k = 0; k < TILT_TANGENTS; k++) {
    float cu = st * TILT_CS[k][0], cv = st * TILT_CS[k][1];
    for (int c = 0; c < 3; c++)
      tangent[k][c] = ct * hair[c] + cu * u[c] + cv * v[c];
  }
}

/* A tilted sector's cone (sector_look.tangent on): its tangents
 * (maps_cone_tangents; `own`: the sector's hair is its strands'), each
 * one's sin theta to the eye (vd: towards it) and width seen from there,
 * once for every light (mp_tilted). */
static void cone_at(sector_look *s, const float *fr, int own, const float vd[3],
                    const satf_fiber_light *lights, int n_lights, float tilt) {
  float e[3], sum = 0.0f;
  maps_cone_tangents(s->hair, fr, own, tilt, s->tangent);
  memcpy(e, vd, sizeof e);
  satf_normalize3f(e);
  for (int k = 0; k < TILT_TANGENTS; k++) {
    const float *t = s->tangent[k];
    float so = satf_dot3f(e, t);
    s->sin_eye[k] = so;
    s->width[k] = sqrtf(fmaxf(1.0f - so * so, 0.0f));
    sum += s->width[k];
  }
  for (int k = 0; k < TILT_TANGENTS; k++)
    s->width[k] = sum > 0.0f ? s->width[k] / sum : 1.0f / TILT_TANGENTS;
  for (int l = 0; l < n_lights; l++)
    light_vector(fr, &lights[l], s->to_light[l]);
}

static void look_at(const satf_maps_fiber *f, const satf_shell_geom *g,
                    size_t q, const float eye[3],
                    const satf_fiber_light *lights, int n_lights, float tilt,
                    column_entry *c, sector_look *s) {
  const float *fr = g->frames + 9 * q;
  s->q = q;
  /* the fibres' own course where the strands gave it (g->hair, the same
   * in every layer of a column, so the entry still serves them all) */
  const float *own = g->hair ? g->hair + 3 * q : NULL;
  if (!c->ready || memcmp(c->axes, fr + 3, sizeof c->axes) ||
      (own && memcmp(c->hair, own, sizeof c->hair))) {
    memcpy(c->axes, fr + 3, sizeof c->axes);
    maps_sector_hair(g, q, c->hair);
    for (int l = 0; l < n_lights; l++) {
      float fall;
      if (lights[l].local[3] == 0.0f)
        c->light[l] = light_direction(fr, c->hair, &lights[l], &fall);
    }
    c->ready = 1;
  }
  memcpy(s->hair, c->hair, sizeof s->hair);
  float vd[3] = {eye[0] - fr[0], eye[1] - fr[1], eye[2] - fr[2]};
  s->view = sector_direction(fr, s->hair, vd);
  for (int l = 0; l < n_lights; l++) {
    s->fall[l] = 1.0f;
    s->light[l] = lights[l].local[3] == 0.0f
                      ? c->light[l]
                      : light_direction(fr, s->hair, &lights[l], &s->fall[l]);
  }
  satf_db_cell_find(f->db, s->view.azimuth, s->light[0].azimuth, &s->key);
  if (tilt > 0.0f)
    cone_at(s, fr, own != NULL, vd, lights, n_lights, tilt);
}

/* The four lobes' M_p of a sector whose fibres cross the hair direction
 * at angle `tilt`, curling about it (satf_scene_density.curl): the mean
 * of M_p over TILT_TANGENTS tangents evenly around that cone, each at its
 * own sin theta to the light and the eye (d'Eon 2011 eq. 7 for M_p at
 * each; the cone is our model of curls, whose fibres' azimuth about the
 * trajectory is uniform along a helix). The records' azimuthal part stays
 * the sector's. */
static v4f mp_tilted(const satf_maps_fiber *f, const sector_look *s, int li) {
  v4f sum = {0.0f, 0.0f, 0.0f, 0.0f};
  for (int k = 0; k < TILT_TANGENTS; k++)
    sum +=
        s->width[k] *
        mp_lookup(f, satf_dot3f(s->to_light[li], s->tangent[k]), s->sin_eye[k]);
  return sum;
}

/* The lobes' orientation-free level (rel_levels) of the samples nb
 * blends, at view minus light azimuth, linear between the bins, over the
 * samples with coverage: lv gets the lobe channels from SATF_DB_CH_R on.
 * 0 when none has coverage. */
static int rel_level(const satf_maps_fiber *f, const satf_db_neighbors *nb,
                     float view, float light, float *lv) {
  int st = rel_stride(f), nbins = f->rel_bins;
  float rel = (view - light) / SATF_TWO_PI_F;
  float pos = (rel - floorf(rel)) * (float)nbins;
  int b0 = (int)pos;
  float t = pos - (float)b0;
  b0 %= nbins;
  int bins[2] = {b0, (b0 + 1) % nbins};
  float bw[2] = {1.0f - t, t};
  float wsum = 0.0f;
  for (int c = 1; c < st; c++)
    lv[c - 1] = 0.0f;
  for (int n = 0; n < nb->count; n++)
    for (int e = 0; e < 2; e++) {
      const float *r =
          f->rel + ((size_t)nb->index[n] * nbins + (size_t)bins[e]) * st;
      float ww = nb->weight[n] * bw[e];
      if (r[0] <= 0.0f || ww <= 0.0f)
        continue;
      for (int c = 1; c < st; c++)
        lv[c - 1] += ww * r[c];
      wsum += ww;
    }
  if (wsum <= 0.0f)
    return 0;
  for (int c = 1; c < st; c++)
    lv[c - 1] /= wsum;
  return 1;
}

/* Per colour, what turns a light's record row (lobes r, tt, tr, ms at M_p
 * mp; alpha in `alpha`, or in key's fourth lanes for a fill light) into
 * one of its orientation-free level (rel_level); 1 where the row or the
 * samples have no coverage or no radiance. The row's own level is that of
 * the HSV row it is laid as: each record sample weighted by its share `cw`
 * of the row's columns (lay_fiber_row resamples the record to the view). */
static v4f level_scale(const satf_maps_fiber *f, const satf_db_neighbors *nb,
                       const sector_look *s, const direction *light, v4f mp,
                       const float *const tt[3], const float *const tr[3],
                       const float *const ms[3], const float *r,
                       const float *alpha, const float *key, const float *cw,
                       int w) {
  v4f one = {1.0f, 1.0f, 1.0f, 1.0f};
  float lv[1 + 3 * 3];
  if (!rel_level(f, nb, s->view.azimuth, light->azimuth, lv))
    return one;
  double sum[3] = {0.0, 0.0, 0.0}, sum_a = 0.0;
  for (int x = 0; x < w; x++) {
    if (cw[x] == 0.0f)
      continue;
    sum_a += cw[x] * (alpha ? alpha[x] : key[4 * x + 3]);
    for (int c = 0; c < 3; c++)
      sum[c] += cw[x] * (mp[0] * r[x] + mp[1] * tt[c][x] + mp[2] * tr[c][x] +
                         mp[3] * ms[c][x]);
  }
  if (sum_a <= 1e-4 * w)
    return one;
  int n = f->levels;
  for (int c = 0; c < 3; c++) {
    int k = f->level_of[c];
    double level = mp[0] * lv[0] + mp[1] * lv[1 + k] + mp[2] * lv[1 + n + k] +
                   mp[3] * lv[1 + 2 * n + k];
    double own = sum[c] / sum_a;
    if (own > 0.0 && level > 0.0)
      one[c] = (float)(level / own);
  }
  return one;
}

/* The record of a boundary sector for every light, summed into key (the
 * first light's radiance, which the deep opacity map and eq. 12 shadow)
 * and fill (the others'): E (M_R R + M_TT TT + M_TRT TRT + M_MS MS)
 * (satf/db.h fibre records, d'Eon 2011 eq. 7 for M_p), per record sample,
 * still premultiplied by coverage. Both hold 4 floats a sample, the
 * colour in 0-2 (interleaved as the texels, for lay_fiber_row); key has
 * the alpha in 3, fill 0. With column weights cw (orientation-free
 * records; NULL: the records' own level) each light's row keeps its
 * structure but takes, per colour, the level (radiance per unit coverage)
 * of its samples' records seen from outside at the same view minus light
 * azimuth (rel_levels), as maps.c's lay_row does for Phong records. */
static void sector_radiance(const satf_maps_fiber *f, const sector_look *s,
                            const satf_db_neighbors *nb,
                            const satf_fiber_light *lights, int n_lights,
                            int trt, float tilt, const float *cw, int w,
                            float *restrict key, float *restrict fill) {
  int n = f->levels;
  /* alpha and the lobes (SATF_DB_CH_ALPHA on): the reflectance channel,
   * a total for Phong-style readers, is never read here */
  float rec[(2 + 3 * 3) * MAPS_MAX_WIDTH];
  if (n_lights < 2) /* no other light: none */
    memset(fill, 0, 4 * (size_t)w * sizeof(float));
  for (int li = 0; li < n_lights; li++) {
    const direction *i = &s->light[li];
    v4f mp = tilt > 0.0f ? mp_tilted(f, s, li)
                         : mp_lookup(f, i->sin_t, s->view.sin_t);
    if (!trt)
      mp[2] = 0.0f;
    /* the other lights from the nearest sample alone: a quarter of the
     * blending for lights that neither shadow nor set the hair's look
     * (the key light's records blend all k, SATF eq. 4); and without
     * alpha, which the key light's look-up gives (a range's values are
     * those of the full look-up, satf_db_lookup_neighbors_range) */
    satf_db_neighbors nearest = {1, {nb->index[0]}, {1.0f}};
    if (li == 0)
      satf_db_lookup_cell_range(f->db, nb, &s->key, SATF_DB_CH_ALPHA,
                                f->channels - SATF_DB_CH_ALPHA, rec);
    else
      satf_db_lookup_neighbors_range(
          f->db, &nearest, s->view.azimuth, i->azimuth, SATF_DB_CH_R,
          f->channels - SATF_DB_CH_R,
          rec + (SATF_DB_CH_R - SATF_DB_CH_ALPHA) * w);
    float *dst = li == 0 ? key : fill;
    const float *r = rec + (SATF_DB_CH_R - SATF_DB_CH_ALPHA) * w, *tt[3],
                *tr[3], *ms[3];
    v4f e = {0.0f, 0.0f, 0.0f, 0.0f};
    for (int c = 0; c < 3; c++) {
      int k = f->level_of[c];
      e[c] = lights[li].rgb[c] * s->fall[li];
      tt[c] = rec + (SATF_DB_CH_TT(k) - SATF_DB_CH_ALPHA) * w;
      tr[c] = rec + (SATF_DB_CH_TRT(k, n) - SATF_DB_CH_ALPHA) * w;
      ms[c] = rec + (SATF_DB_CH_MS(k, n) - SATF_DB_CH_ALPHA) * w;
    }
    /* a sample's three colours at once (each lane the scalar sum, in its
     * order), texels as lay_fiber_row reads them; the key light and the
     * first other one store theirs where a cleared sum was loaded, added
     * to and stored again (perf: build_column's hottest instruction), the
     * further ones add */
    if (cw)
      e *= level_scale(f, li == 0 ? nb : &nearest, s, i, mp, tt, tr, ms, r,
                       li == 0 ? rec : NULL, key, cw, w);
    int add = li > 1;
    for (int x = 0; x < w; x++) {
      v4f vt = {tt[0][x], tt[1][x], tt[2][x], 0.0f};
      v4f vr = {tr[0][x], tr[1][x], tr[2][x], 0.0f};
      v4f vm = {ms[0][x], ms[1][x], ms[2][x], 0.0f};
      v4f v = e * (mp[0] * r[x] + mp[1] * vt + mp[2] * vr + mp[3] * vm);
      if (li == 0)
        v[3] = rec[x]; /* alpha */
      if (add) {
        v4f d;
        memcpy(&d, dst + 4 * x, sizeof d);
        v = d + v;
      }
      memcpy(dst + 4 * x, &v, sizeof v);
    }
  }
}

/* Lays one boundary's radiance (sector_radiance's key and fill) across an
 * HSV row, each texel the key's quad then the fill's (see maps_fiber.h),
 * resampled to the layer's
 * columns as lay_row does, and divided by alpha (eq. 14 multiplies by
 * alpha again); the fill's channel 3 is the s-map sum `sum` of the outer
 * layers (eq. 12), to which this layer's alpha is then added for the next
 * layer in. */
static void lay_fiber_row(const satf_maps *m, const float *restrict key,
                          const float *restrict fill, float view,
                          float *restrict sum, float *restrict row) {
  int w = satf_maps_width(m);
  const uint16_t *idx;
  const float *fr;
  maps_columns(m, view, &idx, &fr);
  for (int x = 0; x < w; x++) {
    v4f k0, k1, f0, f1; /* samples idx[x] and idx[x] + 1 */
    memcpy(&k0, key + 4 * idx[x], sizeof k0);
    memcpy(&k1, key + 4 * idx[x] + 4, sizeof k1);
    memcpy(&f0, fill + 4 * idx[x], sizeof f0);
    memcpy(&f1, fill + 4 * idx[x] + 4, sizeof f1);
    v4f tk = k0 + fr[x] * (k1 - k0),
        tf = f0 + fr[x] * (f1 - f0); /* maps_sample */
    float a = tk[3];
    float inv = a > 1e-4f ? 1.0f / a : 0.0f;
    v4f sk = {inv, inv, inv, 1.0f}, sf = {inv, inv, inv, 0.0f};
    tk *= sk;
    tf *= sf;
    tf[3] = sum[x];
    sum[x] += a;
    memcpy(row + 8 * x, &tk, sizeof tk);
    memcpy(row + 8 * x + 4, &tf, sizeof tf);
  }
}

/* Each record sample's share of an HSV row's columns seen from azimuth
 * `view` (the weights lay_fiber_row resamples it with), into cw[0..w]. */
static void column_weights(const satf_maps *m, float view, float *cw) {
  int w = satf_maps_width(m);
  const uint16_t *idx;
  const float *fr;
  maps_columns(m, view, &idx, &fr);
  memset(cw, 0, ((size_t)w + 1) * sizeof *cw);
  for (int x = 0; x < w; x++) {
    cw[idx[x]] += 1.0f - fr[x];
    cw[idx[x] + 1] += fr[x];
  }
}

/* Fetches ahead the records of sector s's key light look-up (from its
 * cached neighbours; none without a cache): satf_db_prefetch. */
static void prefetch_key(const satf_maps_fiber *f, const satf_shell_geom *g,
                         const sector_look *s, int k_nearest) {
  const satf_db_neighbors *nb = maps_sector_neighbors(g, s->q, k_nearest);
  if (nb)
    satf_db_prefetch_cell(f->db, nb, &s->key, SATF_DB_CH_ALPHA,
                          f->channels - SATF_DB_CH_ALPHA);
}

/* The scratch of one build: a column's s-map sums, (st + 1) x width
 * floats, then its st + 1 column entries (of floats and an int, so
 * aligned as floats are). */
_Static_assert(_Alignof(column_entry) <= _Alignof(float),
               "column entries follow the sums' floats");
#define ENTRY_FLOATS                                                           \
  ((sizeof(column_entry) + sizeof(float) - 1) / sizeof(float))

size_t satf_maps_fiber_scratch_floats(const satf_shell_geom *g, int width) {
  return (size_t)(g->shell.st + 1) * ((size_t)width + ENTRY_FLOATS);
}

/* Column j of layer k; sums holds the s-map sums of the
 * layers outside it per boundary, and gets this layer's alpha added. */
static int build_column(const satf_maps *m, const satf_maps_fiber *f,
                        const satf_shell_geom *g, const float eye[3],
                        const satf_fiber_light *lights, int n_lights, int trt,
                        const satf_map_options *opt, int k, int j,
                        half_pack_fn pack, float *sums, column_entry *column,
                        uint16_t *texels) {
  const satf_shell_params *sh = &g->shell;
  int w = satf_maps_width(m), lookups = 0;
  size_t row_halfs = (size_t)sh->su * (size_t)w * 8;
  uint16_t *layer = texels + (size_t)k * satf_maps_layer_texels(g, w) * 8;
  float key[4 * MAPS_MAX_WIDTH], fill[4 * MAPS_MAX_WIDTH];
  float row[8 * MAPS_MAX_WIDTH];
  /* the boundary records along t, each looked up once: HSV i shows
   * boundary i in row 2i and boundary i + 1 in row 2i + 1 (SATF eq. 7);
   * the current and next boundary's looks swap roles rather than copy */
  sector_look looks[2], *cur = &looks[0], *next = &looks[1];
  look_at(f, g, maps_sector_index(sh, 0, k, j), eye, lights, n_lights,
          opt->tilt, &column[0], cur);
  for (int i = 0; i <= sh->st; i++) {
    if (i < sh->st) { /* the next boundary's records load meanwhile */
      look_at(f, g, maps_sector_index(sh, i + 1, k, j), eye, lights, n_lights,
              opt->tilt, &column[i + 1], next);
      prefetch_key(f, g, next, opt->k_nearest);
    }
    satf_db_neighbors found;
    const satf_db_neighbors *nb =
        maps_sector_neighbors(g, cur->q, opt->k_nearest);
    if (!nb) {
      satf_db_neighbors_find(maps_db(m), g->features + 3 * cur->q,
                             opt->k_nearest, &found);
      nb = &found;
    }
    float cw[MAPS_MAX_WIDTH + 1];
    if (opt->orientation_free)
      column_weights(m, cur->view.azimuth, cw);
    sector_radiance(f, cur, nb, lights, n_lights, trt, opt->tilt,
                    opt->orientation_free ? cw : NULL, w, key, fill);
    lookups += n_lights;
    lay_fiber_row(m, key, fill, cur->view.azimuth, sums + (size_t)i * w, row);
    /* the top row of HSV i and the bottom row of HSV i - 1, the same
     * texels */
    size_t col = (size_t)j * w * 8;
    for (int r = i > 0 ? 2 * i - 1 : 0; r <= 2 * i && r < 2 * sh->st; r++)
      pack(row, layer + (size_t)r * row_halfs + col, (size_t)w * 8);
    sector_look *t = cur;
    cur = next;
    next = t;
  }
  return lookups;
}

int satf_maps_fiber_build(const satf_maps *m, const satf_maps_fiber *f,
                          const satf_shell_geom *g, const float eye[3],
                          const satf_fiber_light *lights, int n_lights, int trt,
                          const satf_map_options *opt, int part, int parts,
                          float *sums, uint16_t *texels) {
  /* a column of HSVs at a time, from the outer layer in, so that each
   * layer's s-map sum (eq. 12) is the running sum of the alpha laid before
   * it: the maps are written once, as halfs, where a float copy, a pass
   * for the sums and one to pack would write and read them three times
   * more; and the column's layers share its lights' directions
   * (column_entry) */
  int su = g->shell.su, w = satf_maps_width(m);
  int j0 = (int)((long)su * part / parts),
      j1 = (int)((long)su * (part + 1) / parts);
  size_t nsums = (size_t)(g->shell.st + 1) * (size_t)w;
  column_entry *column = (column_entry *)(sums + nsums);
  half_pack_fn pack = half_stream_packer();
  int lookups = 0;
  for (int j = j0; j < j1; j++) {
    memset(sums, 0, nsums * sizeof(float));
    for (int i = 0; i <= g->shell.st; i++)
      column[i].ready = 0;
    for (int k = g->shell.layers - 1; k >= 0; k--)
      lookups += build_column(m, f, g, eye, lights, n_lights, trt, opt, k, j,
                              pack, sums, column, texels);
  }
  half_stream_end();
  return lookups;
}
