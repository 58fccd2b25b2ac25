/* maps.c - see maps.h. */
#include "maps.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "satf/math.h"

/* Resampling tables are kept for this many view azimuths. */
#define AZIMUTH_BINS MAPS_AZIMUTH_BINS

/* The next geometry's serial (satf_shell_geom.serial); atomic, for
 * renderers built on several threads at once. */
static _Atomic unsigned long next_serial;

size_t satf_shell_sector_count(const satf_shell_params *s) {
  return (size_t)(s->st + 1) * (size_t)s->layers * (size_t)s->su;
}

/* Index of sector (i, k, j), and of HSV (i, k, j) (between sectors i and
 * i + 1): the same layout over st + 1 or st rows. */
static size_t sector_index(const satf_shell_params *s, int i, int k, int j) {
  return ((size_t)i * (size_t)s->layers + (size_t)k) * (size_t)s->su +
         (size_t)j;
}

satf_status satf_shell_geom_create(const satf_cluster *cluster,
                                   const satf_shell_params *shell,
                                   satf_shell_geom *g, satf_error *err) {
  memset(g, 0, sizeof *g);
  satf_status st = satf_shell_params_check(shell, err);
  if (st != SATF_OK)
    return st;
  g->shell = *shell;
  g->serial = ++next_serial;
  size_t n = satf_shell_sector_count(shell);
  g->frames = malloc(n * 9 * sizeof(float));
  g->features = calloc(n * 3, sizeof(float));
  if (!g->frames || !g->features) {
    satf_shell_geom_destroy(g);
    return satf_error_set(err, SATF_ERR_NOMEM, "cannot allocate %zu sectors",
                          n);
  }
  for (int i = 0; i <= shell->st; i++) {
    satf_cluster_section sec;
    satf_cluster_section_at(cluster, (float)i / (float)shell->st, &sec);
    for (int k = 0; k < shell->layers; k++) {
      float v = 0.5f * (satf_shell_layer_v(shell, k) +
                        satf_shell_layer_v(shell, k + 1));
      for (int j = 0; j < shell->su; j++) {
        float u = SATF_TWO_PI_F * ((float)j + 0.5f) / (float)shell->su;
        float *f = g->frames + 9 * sector_index(shell, i, k, j);
        satf_cluster_section_point(&sec, v, u, f);
        /* In the normal plane, the ellipse point moves along
         * (-A sin u, B cos u) as u grows; its outward normal is
         * (B cos u, A sin u) in the ellipse's axes (n1, n2), which the
         * section has already turned by the twist (SATF eq. 1,
         * satf/geometry.h). */
        float c = cosf(u), s = sinf(u);
        for (int a = 0; a < 3; a++) {
          f[3 + a] = sec.b * c * sec.n1[a] + sec.a * s * sec.n2[a];
          f[6 + a] = -sec.a * s * sec.n1[a] + sec.b * c * sec.n2[a];
        }
        satf_normalize3f(f + 3);
        satf_normalize3f(f + 6);
      }
    }
  }
  return SATF_OK;
}

struct satf_neighbor_cache {
  int k;
  satf_db_neighbors *sector; /* per sector */
  satf_db_neighbors *hsv;    /* per HSV (i, k, j): averaged features */
};

void satf_neighbor_cache_free(satf_neighbor_cache *c) {
  if (c) {
    free(c->sector);
    free(c->hsv);
    free(c);
  }
}

void satf_shell_geom_destroy(satf_shell_geom *g) {
  free(g->frames);
  free(g->features);
  free(g->hair);
  satf_neighbor_cache_free(g->neighbors);
  g->frames = g->features = g->hair = NULL;
  g->neighbors = NULL;
}

void maps_sector_hair(const satf_shell_geom *g, size_t q, float hair[3]) {
  if (g->hair) {
    memcpy(hair, g->hair + 3 * q, 3 * sizeof(float));
    return;
  }
  const float *fr = g->frames + 9 * q;
  satf_cross3f(fr + 3, fr + 6, hair);
  satf_normalize3f(hair);
}

satf_status satf_shell_geom_set_hair(satf_shell_geom *g, const float *dirs,
                                     satf_error *err) {
  size_t n = satf_shell_sector_count(&g->shell);
  float *hair = malloc(n * 3 * sizeof(float));
  if (!hair)
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot allocate the hair of %zu sectors", n);
  for (size_t q = 0; q < n; q++) {
    const float *fr = g->frames + 9 * q, *d = dirs + 3 * q;
    float *h = hair + 3 * q, dn = satf_dot3f(d, fr + 3);
    for (int c = 0; c < 3; c++)
      h[c] = d[c] - dn * fr[3 + c];
    float len = sqrtf(satf_dot3f(h, h));
    if (len > 1e-3f) /* at least 0.06 degrees off N */
      for (int c = 0; c < 3; c++)
        h[c] /= len;
    else {
      satf_cross3f(fr + 3, fr + 6, h);
      satf_normalize3f(h);
    }
  }
  free(g->hair);
  g->hair = hair;
  g->serial = ++next_serial;
  return SATF_OK;
}

struct satf_maps {
  const satf_db *db;
  int width;
  float re_scale; /* 1 / unshadowed hair's reflectance (reflectance_scale) */
  /* per database sample: its reflectance per unit coverage over all its
   * view and light azimuths (sample_mean_reflectance) */
  float *sample_re;
  float lo[SATF_FEATURES], scale[SATF_FEATURES];
  uint16_t *index; /* AZIMUTH_BINS x width: record sample left of column x */
  float *frac;     /* AZIMUTH_BINS x width: weight of the sample after it */
};

satf_status satf_maps_prepare(const satf_maps *m, satf_shell_geom *g,
                              const satf_map_options *opt, satf_error *err) {
  const satf_shell_params *sh = &g->shell;
  size_t ns = satf_shell_sector_count(sh);
  size_t nh = (size_t)sh->st * (size_t)sh->layers * (size_t)sh->su;
  satf_neighbor_cache *c = calloc(1, sizeof *c);
  if (c) {
    c->sector = malloc(ns * sizeof *c->sector);
    c->hsv = malloc(nh * sizeof *c->hsv);
  }
  if (!c || !c->sector || !c->hsv) {
    satf_neighbor_cache_free(c);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot cache the neighbours of %zu sectors", ns);
  }
  c->k = opt->k_nearest;
  for (size_t q = 0; q < ns; q++)
    satf_db_neighbors_find(m->db, g->features + 3 * q, c->k, &c->sector[q]);
  for (int i = 0; i < sh->st; i++)
    for (int k = 0; k < sh->layers; k++)
      for (int j = 0; j < sh->su; j++) {
        const float *a = g->features + 3 * sector_index(sh, i, k, j);
        const float *b = g->features + 3 * sector_index(sh, i + 1, k, j);
        float ave[3] = {0.5f * (a[0] + b[0]), 0.5f * (a[1] + b[1]),
                        0.5f * (a[2] + b[2])};
        satf_db_neighbors_find(m->db, ave, c->k,
                               &c->hsv[sector_index(sh, i, k, j)]);
      }
  g->neighbors = c;
  g->serial = ++next_serial;
  return SATF_OK;
}

/* k = 4 (measured by tests/render/bench_lookup, docs/method.md
 * "Look-up defaults"): against k = 1 it lowers the held-out error 14% (with
 * 16 x 16 feature nodes) and the change of the looked-up records between
 * neighbouring HSVs 25-45% (reflectance), for 1.3-1.5x the map stage;
 * k = 8 gains 1-2% more accuracy for 1.7-2.2x. */
satf_map_options satf_map_options_default(void) {
  satf_map_options o = {0.05f, 4, 1, 0.0f};
  return o;
}

/* The scale of reflectance: 1 / the reflectance per unit coverage of hair
 * that nothing shadows. SATF eq. 13 multiplies the lighting (eq. 8-11, whose
 * k_dif, k_speI, k_speII and colours are the hair's material) by re and
 * says nothing of re's scale. Our reading: re says what the sector's
 * structure does to that lighting (which parts of the record are lit,
 * highlights, the strands shadowed by the strands of the same sector
 * between them and the light) relative to a strand that nothing shadows,
 * which eq. 9-11 light in full. So one scale for the whole database, that
 * of unshadowed hair, and a record keeps its own shadowing (shade_fs.glsl:
 * the records own the attenuation inside an HSV, eq. 12 the cluster's
 * outer layers, the deep opacity map the other clusters).
 *
 * The tracer shadows strands by the density between them and the light
 * (trace.c), so re / alpha falls with density (default database: 0.274
 * for rho_st < 0.05, 0.181 above 1.6, flat at 0.285 with --no-shadow),
 * and unshadowed hair is what the sparsest samples tend to: the intercept
 * at rho_st = 0 of a coverage-weighted straight line through re / alpha
 * against rho_st over the sparser half of the samples with coverage
 * (default database: 0.279; the sparsest quarter gives 0.279 too), at least
 * their mean (shadowing only lowers re, a rising fit is noise). Before,
 * each sample was scaled to a mean of 1 over all its view and light
 * azimuths, which lifted dense hair by its own shadowing averaged over the
 * light's directions: lit from the viewer's side (where its front strands
 * are unshadowed, 1.48x the sample's mean above rho_st 1.6), dense
 * clusters came out up to 1.5x too bright, the imported ponytail 1.36x
 * its strands (satf-render --strands), now 1.05x. */
typedef struct sample_reflectance {
  float rho;     /* rho_st */
  double re, al; /* sums over all records */
} sample_reflectance;

static int by_density(const void *a, const void *b) {
  float x = ((const sample_reflectance *)a)->rho;
  float y = ((const sample_reflectance *)b)->rho;
  return (x > y) - (x < y);
}

/* The weighted straight line's intercept at rho 0 over s[0..n), at least
 * the weighted mean. */
static double unshadowed_reflectance(const sample_reflectance *s, int n) {
  double sw = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  for (int i = 0; i < n; i++) {
    double w = s[i].al, x = s[i].rho, y = s[i].re / s[i].al;
    sw += w, sx += w * x, sy += w * y, sxx += w * x * x, sxy += w * x * y;
  }
  double mx = sx / sw, my = sy / sw, var = sxx / sw - mx * mx;
  if (!(var > 1e-12 * (1.0 + mx * mx)))
    return my;
  double slope = (sxy / sw - mx * my) / var, at0 = my - slope * mx;
  return at0 > my ? at0 : my;
}

/* Whether azimuth i of n (2 pi i / n from the sector's outward normal,
 * trace.h) lies on the outer side of the sector. A sample's level
 * (sample_re) is its reflectance per unit coverage seen and lit from that
 * side, as the outer face of a sheet of hair is: over every azimuth it
 * would count records lit from inside the cluster, which its shells and
 * the deep opacity map already darken (the curtain above: 0.83 of the
 * strands' mean luminance, 0.94 from the outer side). */
static int front(int i, int n) { return 4 * i < n || 4 * i > 3 * n; }

static satf_status reflectance_scale(const satf_db *db, float *scale,
                                     float *sample_re, satf_error *err) {
  const satf_build_params *p = satf_db_params(db);
  sample_reflectance *s = malloc((size_t)p->samples * sizeof *s);
  if (!s)
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot allocate %d samples' sums", p->samples);
  int n = 0;
  for (int i = 0; i < p->samples; i++) {
    double sum_re = 0.0, sum_al = 0.0, front_re = 0.0, front_al = 0.0;
    for (int iv = 0; iv < p->n_view; iv++)
      for (int il = 0; il < p->n_light; il++) {
        const float *re, *al;
        satf_db_record(db, i, iv, il, &re, &al);
        double r = 0.0, a = 0.0;
        for (int j = 0; j < p->trace.width; j++) {
          r += re[j];
          a += al[j];
        }
        sum_re += r;
        sum_al += a;
        if (front(iv, p->n_view) && front(il, p->n_light)) {
          front_re += r;
          front_al += a;
        }
      }
    sample_re[i] = front_al > 1e-3 ? (float)(front_re / front_al) : 0.0f;
    if (sum_re > 0.0 && sum_al > 1e-3) /* samples without coverage: none */
      s[n++] = (sample_reflectance){satf_db_features(db, i)[0], sum_re, sum_al};
  }
  qsort(s, (size_t)n, sizeof *s, by_density);
  /* the sparser half, at least two samples (all where fewer) */
  double re = n > 0 ? unshadowed_reflectance(s, n < 4 ? n : (n + 1) / 2) : 0.0;
  *scale = re > 0.0 ? (float)(1.0 / re) : 1.0f;
  free(s);
  return SATF_OK;
}

float maps_reflectance_scale(const satf_maps *m) { return m->re_scale; }

satf_status satf_maps_create(const satf_db *db, satf_maps **out,
                             satf_error *err) {
  *out = NULL;
  satf_maps *m = calloc(1, sizeof *m);
  if (!m)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  int w = satf_db_width(db);
  if (w < 2 || w > MAPS_MAX_WIDTH) {
    free(m);
    return satf_error_set(err, SATF_ERR_INCOMPATIBLE,
                          "database records of %d samples: the renderer "
                          "supports 2 to %d",
                          w, MAPS_MAX_WIDTH);
  }
  m->db = db;
  m->width = w;
  float hi[SATF_FEATURES];
  satf_db_feature_range(db, m->lo, hi);
  for (int a = 0; a < SATF_FEATURES; a++)
    m->scale[a] = hi[a] > m->lo[a] ? 1.0f / (hi[a] - m->lo[a]) : 1.0f;
  m->index = malloc((size_t)AZIMUTH_BINS * w * sizeof *m->index);
  m->frac = malloc((size_t)AZIMUTH_BINS * w * sizeof *m->frac);
  m->sample_re =
      malloc(((size_t)satf_db_params(db)->samples + 1) * sizeof *m->sample_re);
  if (!m->index || !m->frac || !m->sample_re) {
    satf_maps_destroy(m);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  satf_status st = reflectance_scale(db, &m->re_scale, m->sample_re, err);
  if (st != SATF_OK) {
    satf_maps_destroy(m);
    return st;
  }
  const satf_sector_shape *shape = &satf_db_params(db)->shape;
  for (int b = 0; b < AZIMUTH_BINS; b++) {
    float theta = SATF_TWO_PI_F * (float)b / AZIMUTH_BINS;
    float e[2] = {-sinf(theta), cosf(theta)}, pmin, pmax;
    satf_trace_extent(shape, theta, &pmin, &pmax);
    for (int x = 0; x < w; x++) {
      /* the point at phase fraction f on the sector's outer arc, projected
       * on the screen axis, in record samples (trace.h layout) */
      float f = ((float)x + 0.5f) / (float)w;
      float phi = (f - 0.5f) * shape->phase_span;
      float pe = shape->r_outer * (cosf(phi) * e[0] + sinf(phi) * e[1]);
      float xr = (pe - pmin) / (pmax - pmin) * (float)w - 0.5f;
      if (xr < 0.0f)
        xr = 0.0f;
      if (xr > (float)(w - 1))
        xr = (float)(w - 1);
      int i0 = (int)xr;
      if (i0 > w - 2)
        i0 = w - 2;
      m->index[b * w + x] = (uint16_t)i0;
      m->frac[b * w + x] = xr - (float)i0;
    }
  }
  *out = m;
  return SATF_OK;
}

void satf_maps_destroy(satf_maps *m) {
  if (m) {
    free(m->index);
    free(m->frac);
    free(m->sample_re);
    free(m);
  }
}

int satf_maps_width(const satf_maps *maps) { return maps->width; }

size_t maps_hsv_texels(int width) { return (size_t)width * 2; }

size_t satf_maps_layer_texels(const satf_shell_geom *g, int width) {
  return (size_t)g->shell.su * (size_t)g->shell.st * maps_hsv_texels(width);
}

float maps_azimuth(const float *frame, const float d[3]) {
  float x = satf_dot3f(d, frame + 3);
  float y = satf_dot3f(d, frame + 6);
  float a = atan2f(y, x);
  return a < 0.0f ? a + SATF_TWO_PI_F : a;
}

void satf_maps_angles(const satf_shell_geom *g, const float eye[3],
                      const float light[4], float *angles) {
  size_t n = satf_shell_sector_count(&g->shell);
  for (size_t s = 0; s < n; s++) {
    const float *f = g->frames + 9 * s;
    float v[3] = {eye[0] - f[0], eye[1] - f[1], eye[2] - f[2]};
    float l[3] = {light[0] - light[3] * f[0], light[1] - light[3] * f[1],
                  light[2] - light[3] * f[2]};
    angles[2 * s] = maps_azimuth(f, v);
    angles[2 * s + 1] = maps_azimuth(f, l);
  }
}

/* Signed smallest difference b - a of two angles, in (-pi, pi]. */
static float angle_diff(float a, float b) {
  float d = fmodf(b - a, SATF_TWO_PI_F);
  if (d > SATF_PI_F)
    d -= SATF_TWO_PI_F;
  if (d <= -SATF_PI_F)
    d += SATF_TWO_PI_F;
  return d;
}

typedef struct params {
  float f[SATF_FEATURES];
  float view, light;
} params;

/* SATF eq. 6: ||Params(top) - Params(bottom)||, features scaled to [0, 1]
 * over the database and angles in units of pi. */
static float params_distance(const satf_maps *m, const params *a,
                             const params *b) {
  float d2 = 0.0f;
  for (int k = 0; k < SATF_FEATURES; k++) {
    float d = (a->f[k] - b->f[k]) * m->scale[k];
    d2 += d * d;
  }
  float dv = angle_diff(a->view, b->view) / SATF_PI_F;
  float dl = angle_diff(a->light, b->light) / SATF_PI_F;
  return sqrtf(d2 + dv * dv + dl * dl);
}

static params params_average(const params *a, const params *b) {
  params p;
  for (int k = 0; k < SATF_FEATURES; k++)
    p.f[k] = 0.5f * (a->f[k] + b->f[k]);
  p.view = a->view + 0.5f * angle_diff(a->view, b->view);
  p.light = a->light + 0.5f * angle_diff(a->light, b->light);
  return p;
}

void maps_columns(const satf_maps *m, float view, const uint16_t **index,
                  const float **frac) {
  float turns = view / SATF_TWO_PI_F;
  turns -= floorf(turns); /* any angle, into [0, 1) */
  int b = (int)(turns * AZIMUTH_BINS + 0.5f) % AZIMUTH_BINS;
  *index = m->index + (size_t)b * m->width;
  *frac = m->frac + (size_t)b * m->width;
}

size_t maps_sector_index(const satf_shell_params *s, int i, int k, int j) {
  return sector_index(s, i, k, j);
}

const satf_db *maps_db(const satf_maps *m) { return m->db; }

const satf_db_neighbors *maps_sector_neighbors(const satf_shell_geom *g,
                                               size_t q, int k) {
  return g->neighbors && g->neighbors->k == k ? &g->neighbors->sector[q] : NULL;
}

const satf_db_neighbors *maps_hsv_neighbors(const satf_shell_geom *g, size_t q,
                                            int k) {
  return g->neighbors && g->neighbors->k == k ? &g->neighbors->hsv[q] : NULL;
}

void maps_column_table(const satf_maps *m, const uint16_t **index,
                       const float **frac) {
  *index = m->index;
  *frac = m->frac;
}

const float *maps_sample_levels(const satf_maps *m) { return m->sample_re; }

/* Lays a record across one HSV row (see maps.h), with the reflectance
 * divided by alpha: eq. 5 accumulates reflectance weighted by opacity, and
 * eq. 14 multiplies by alpha again, so keeping it would count coverage
 * twice (our reading; the paper multiplies re and alpha without comment),
 * and times the database's scale (reflectance_scale). */
static void lay_row(const satf_maps *m, const float *re, const float *al,
                    float view, float density, float level, float *row) {
  int w = m->width;
  const uint16_t *idx;
  const float *fr;
  maps_columns(m, view, &idx, &fr);
  /* The row's reflectance per unit coverage, which `level` replaces when
   * given. A record's level follows its sector's azimuths (SATF eq. 4: the
   * tracer's Phong term and in-sector shadowing, trace.c), and across a
   * cluster those turn with the shell's normal, so every cluster drew as a
   * shaded cylinder: on a generated curtain of 20,000 straight strands
   * (64 overlapping clusters) the column luminance of the front clusters
   * ran 1.09x brighter at their centres than between them, with shadows
   * off 1.08x, against 1.00 for the strands (satf-render --strands), which
   * eq. 9-11 light by their tangent alone. Hair of overlapping clusters has
   * no such cylinders: its lighting is eq. 8-11's, its shadowing eq. 12's
   * s-map and the deep opacity map's. So the record keeps what varies
   * across it (strands and gaps, where each is lit) and the level of its
   * density: now 1.00x (SSIM4 against the strands 0.33 -> 0.39). */
  double sum_r = 0.0, sum_a = 0.0;
  for (int x = 0; x < w; x++) {
    sum_r += maps_sample(re, idx[x], fr[x]);
    sum_a += maps_sample(al, idx[x], fr[x]);
  }
  float scale = m->re_scale;
  if (level > 0.0f && sum_r > 0.0 && sum_a > 1e-4 * w)
    scale *= level / (float)(sum_r / sum_a);
  for (int x = 0; x < w; x++) {
    float r = maps_sample(re, idx[x], fr[x]);
    float a = maps_sample(al, idx[x], fr[x]);
    /* the s-map sum (2) is filled by satf_maps_shadow_sums; one store of
     * the whole texel, which misses the cache (the maps are tens of MB) */
    float t[4] = {a > 1e-4f ? scale * r / a : 0.0f, a, 0.0f, density};
    memcpy(row + 4 * x, t, sizeof t);
  }
}

/* The look-up parameters of sector q: its features and azimuths. */
static params sector_params(const satf_shell_geom *g, const float *angles,
                            size_t q) {
  params p;
  memcpy(p.f, g->features + 3 * q, sizeof p.f);
  p.view = angles[2 * q];
  p.light = angles[2 * q + 1];
  return p;
}

/* A record at p (SATF eq. 4): from the cached neighbours nb when there
 * are some, else from the k nearest samples; rec gets reflectance, then
 * alpha at rec + width. *level: the same blend of the samples' reflectance
 * per unit coverage over all azimuths when opt->orientation_free, else 0
 * (lay_row keeps the record's own). */
static void lookup(const satf_maps *m, const satf_db_neighbors *nb,
                   const params *p, const satf_map_options *opt, float *rec,
                   float *level) {
  satf_db_neighbors found;
  if (!nb) {
    satf_db_neighbors_find(m->db, p->f, opt->k_nearest, &found);
    nb = &found;
  }
  satf_db_lookup_neighbors_range(m->db, nb, p->view, p->light,
                                 SATF_DB_CH_REFLECTANCE, 2, rec);
  /* over the samples with coverage (a sample of none has no level) */
  float l = 0.0f, wsum = 0.0f;
  if (opt->orientation_free)
    for (int n = 0; n < nb->count; n++)
      if (m->sample_re[nb->index[n]] > 0.0f) {
        l += nb->weight[n] * m->sample_re[nb->index[n]];
        wsum += nb->weight[n];
      }
  *level = wsum > 0.0f ? l / wsum : 0.0f;
}

/* Whether sector q's azimuths differ from those of its last look-up
 * (NaN: never looked up). */
static int sector_moved(const float *angles, const float *prev, size_t q) {
  return angles[2 * q] != prev[2 * q] || angles[2 * q + 1] != prev[2 * q + 1];
}

/* What HSV (i, k, j) looks up: nothing (its sectors' azimuths are those
 * of its last look-up), one record at its averaged parameters (uniform,
 * SATF sec. 6.2.2) or its two boundary sectors' (eq. 7). */
typedef struct hsv_plan {
  enum { HSV_KEEP, HSV_UNIFORM, HSV_TWO } kind;
  size_t st0, st1; /* its sectors */
  params top, bot; /* their parameters */
  params ave;      /* HSV_UNIFORM: the averaged parameters */
  const satf_db_neighbors *nb_ave, *nb_top, *nb_bot; /* cached, or NULL */
} hsv_plan;

static void plan_hsv(const satf_maps *m, const satf_shell_geom *g,
                     const float *angles, const float *prev,
                     const satf_map_options *opt, const satf_neighbor_cache *nc,
                     int i, int k, int j, hsv_plan *h) {
  const satf_shell_params *sh = &g->shell;
  h->st0 = sector_index(sh, i, k, j);
  h->st1 = sector_index(sh, i + 1, k, j);
  /* an HSV's texels follow from its two sectors' parameters alone
   * (features and neighbours are fixed): the same azimuths, the same
   * texels */
  if (prev && !sector_moved(angles, prev, h->st0) &&
      !sector_moved(angles, prev, h->st1)) {
    h->kind = HSV_KEEP;
    return;
  }
  h->top = sector_params(g, angles, h->st0);
  h->bot = sector_params(g, angles, h->st1);
  h->nb_ave = nc ? &nc->hsv[h->st0] : NULL;
  h->nb_top = nc ? &nc->sector[h->st0] : NULL;
  h->nb_bot = nc ? &nc->sector[h->st1] : NULL;
  if (params_distance(m, &h->top, &h->bot) < opt->k_threshold) {
    h->kind = HSV_UNIFORM;
    h->ave = params_average(&h->top, &h->bot);
  } else {
    h->kind = HSV_TWO;
  }
}

/* Fetches the records of HSV h's last look-up ahead (satf_db_prefetch);
 * its top record, when it has two, is mostly the HSV before's bottom. */
static void prefetch_hsv(const satf_maps *m, const hsv_plan *h) {
  if (h->kind == HSV_UNIFORM && h->nb_ave)
    satf_db_prefetch(m->db, h->nb_ave, h->ave.view, h->ave.light,
                     SATF_DB_CH_REFLECTANCE, 2);
  else if (h->kind == HSV_TWO && h->nb_bot)
    satf_db_prefetch(m->db, h->nb_bot, h->bot.view, h->bot.light,
                     SATF_DB_CH_REFLECTANCE, 2);
}

int satf_maps_build_layer(const satf_maps *m, const satf_shell_geom *g,
                          const float *angles, const satf_map_options *opt,
                          int k, float *texels) {
  return satf_maps_update_layer(m, g, angles, NULL, opt, k, texels);
}

int satf_maps_update_layer(const satf_maps *m, const satf_shell_geom *g,
                           const float *angles, const float *prev,
                           const satf_map_options *opt, int k, float *texels) {
  const satf_shell_params *sh = &g->shell;
  int w = m->width, lookups = 0, kn = opt->k_nearest;
  size_t row_floats = (size_t)sh->su * (size_t)w * 4;
  /* reflectance then alpha, of the HSV's top and bottom records */
  float top_rec[2 * MAPS_MAX_WIDTH], bot_rec[2 * MAPS_MAX_WIDTH];
  float top_level = 0.0f, bot_level = 0.0f;
  const satf_neighbor_cache *nc =
      g->neighbors && g->neighbors->k == kn ? g->neighbors : NULL;
  for (int j = 0; j < sh->su; j++) {
    int have_top = 0; /* the previous HSV's bottom record is this top's */
    hsv_plan cur, next;
    plan_hsv(m, g, angles, prev, opt, nc, 0, k, j, &next);
    for (int i = 0; i < sh->st; i++) {
      cur = next;
      if (i + 1 < sh->st) { /* the next HSV's records load meanwhile */
        plan_hsv(m, g, angles, prev, opt, nc, i + 1, k, j, &next);
        prefetch_hsv(m, &next);
      }
      if (cur.kind == HSV_KEEP) {
        have_top = 0;
        continue;
      }
      float *row0 = texels + (size_t)(2 * i) * row_floats + (size_t)j * w * 4;
      float *row1 = row0 + row_floats;
      float dens = 0.5f * (cur.top.f[0] + cur.bot.f[0]);
      if (cur.kind == HSV_UNIFORM) {
        /* uniform HSV: one look-up at the averaged parameters, swept along
         * the HSV (SATF sec. 6.2.2); the HSV's index is its top sector's */
        lookup(m, cur.nb_ave, &cur.ave, opt, top_rec, &top_level);
        lookups++;
        lay_row(m, top_rec, top_rec + w, cur.ave.view, dens, top_level, row0);
        memcpy(row1, row0, (size_t)w * 4 * sizeof(float));
        have_top = 0;
      } else {
        /* two look-ups, interpolated along the HSV by the texture fetch
         * (SATF eq. 7) */
        if (!have_top) {
          lookup(m, cur.nb_top, &cur.top, opt, top_rec, &top_level);
          lookups++;
        }
        lookup(m, cur.nb_bot, &cur.bot, opt, bot_rec, &bot_level);
        lookups++;
        lay_row(m, top_rec, top_rec + w, cur.top.view, dens, top_level, row0);
        lay_row(m, bot_rec, bot_rec + w, cur.bot.view, dens, bot_level, row1);
        memcpy(top_rec, bot_rec, 2 * (size_t)w * sizeof(float));
        top_level = bot_level;
        have_top = 1;
      }
    }
  }
  return lookups;
}

/* SATF eq. 12: the light reaching layer k is attenuated by the alpha of the
 * layers that cover it, m > k, at the same (u, v). */
void satf_maps_shadow_sums(const satf_shell_geom *g, int width, float *texels) {
  int layers = g->shell.layers;
  size_t n = satf_maps_layer_texels(g, width);
  float *outer = texels + (size_t)(layers - 1) * n * 4;
  for (size_t x = 0; x < n; x++)
    outer[4 * x + 2] = 0.0f;
  for (int k = layers - 2; k >= 0; k--) {
    float *cur = texels + (size_t)k * n * 4, *up = cur + n * 4;
    for (size_t x = 0; x < n; x++)
      cur[4 * x + 2] = up[4 * x + 2] + up[4 * x + 1];
  }
}

/* One pair of texels into the seam sums (see maps.h). */
static void seam_pair(const float *a, const float *b, double *re, long *n_re,
                      double *al, long *n_al) {
  *al += fabsf(a[1] - b[1]);
  (*n_al)++;
  if (a[1] > 0.05f && b[1] > 0.05f) {
    *re += fabsf(a[0] - b[0]);
    (*n_re)++;
  }
}

void satf_maps_seams_add(const satf_shell_geom *g, int width,
                         const float *texels, satf_maps_seams *acc) {
  const satf_shell_params *sh = &g->shell;
  int cols = sh->su * width;
  for (int r = 0; r < 2 * sh->st; r++) {
    const float *row = texels + (size_t)r * (size_t)cols * 4;
    for (int c = 0; c < cols; c++) {
      /* the texture wraps around the phase (GL_REPEAT) */
      const float *a = row + 4 * c, *b = row + 4 * ((c + 1) % cols);
      seam_pair(a, row + 4 * ((c + width) % cols), &acc->re_hsv, &acc->n_re_hsv,
                &acc->al_hsv, &acc->n_al_hsv);
      if ((c + 1) % width == 0)
        seam_pair(a, b, &acc->re_edge, &acc->n_re_edge, &acc->al_edge,
                  &acc->n_al_edge);
      else
        seam_pair(a, b, &acc->re_inner, &acc->n_re_inner, &acc->al_inner,
                  &acc->n_al_inner);
    }
  }
  for (int i = 0; i + 1 < sh->st; i++) {
    const float *r1 = texels + (size_t)(2 * i + 1) * (size_t)cols * 4;
    const float *r2 = r1 + (size_t)cols * 4;
    for (int c = 0; c < cols; c++)
      seam_pair(r1 + 4 * c, r2 + 4 * c, &acc->re_t, &acc->n_re_t, &acc->al_t,
                &acc->n_al_t);
  }
}

void satf_maps_seams_ratio(const satf_maps_seams *a, double *re,
                           double *alpha) {
  *re = a->n_re_edge && a->n_re_inner && a->re_inner > 0.0
            ? (a->re_edge / (double)a->n_re_edge) /
                  (a->re_inner / (double)a->n_re_inner)
            : 0.0;
  *alpha = a->n_al_edge && a->n_al_inner && a->al_inner > 0.0
               ? (a->al_edge / (double)a->n_al_edge) /
                     (a->al_inner / (double)a->n_al_inner)
               : 0.0;
}
