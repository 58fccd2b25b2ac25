/* test_maps.c - the SATF step of the online phase on the CPU (maps.h,
 * density.h): sector frames and azimuths of a straight cluster, the layout
 * of the re/alpha maps against direct database look-ups (SATF eq. 4, 6, 7),
 * the s-map sums of eq. 12 and the density features (sec. 5.2) of a
 * procedural density. No GL. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
/* cmocka needs the headers above first */
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "maps.h"
#include "render_fixture.h"
#include "satf/density.h"
#include "satf/geometry.h"
#include "satf/math.h"

#define PI 3.14159265358979323846
#define LENGTH 10.0f

typedef struct fixture {
  satf_db *db;
  satf_maps *maps;
  satf_cluster *cluster; /* straight, along +y from the origin, radius 1 */
  satf_shell_params shell;
  satf_shell_geom geom;
} fixture;

static int setup(void **state) {
  fixture *f = calloc(1, sizeof *f);
  satf_error err;
  if (!f || !(f->db = fixture_db()))
    return -1;
  if (satf_maps_create(f->db, &f->maps, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return -1;
  }
  const float traj[6] = {0, 0, 0, 0, LENGTH, 0};
  const float one = 1.0f, zero = 0.0f;
  satf_cluster_desc desc = {2, traj, 1, &one, &one, &zero};
  if (satf_cluster_create(&desc, &f->cluster, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return -1;
  }
  satf_shell_params sh = {4, 6, 5, 0.5f};
  f->shell = sh;
  if (satf_shell_geom_create(f->cluster, &f->shell, &f->geom, &err) !=
      SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return -1;
  }
  *state = f;
  return 0;
}

static int teardown(void **state) {
  fixture *f = *state;
  satf_shell_geom_destroy(&f->geom);
  satf_cluster_destroy(f->cluster);
  satf_maps_destroy(f->maps);
  satf_db_destroy(f->db);
  free(f);
  return 0;
}

static size_t sector(const satf_shell_params *s, int i, int k, int j) {
  return ((size_t)i * (size_t)s->layers + (size_t)k) * (size_t)s->su +
         (size_t)j;
}

static double circular_diff(double a, double b) {
  double d = fmod(fabs(a - b), 2 * PI);
  return d > PI ? 2 * PI - d : d;
}

/* Sector centres of a straight round cluster of radius 1 along y lie at
 * height LENGTH * i / st, at the middle radius of their layer, with the
 * outward normal radial and the phase direction horizontal. */
static void test_sector_frames(void **state) {
  fixture *f = *state;
  const satf_shell_params *sh = &f->shell;
  assert_int_equal(satf_shell_sector_count(sh),
                   (size_t)(sh->st + 1) * sh->layers * sh->su);
  for (int i = 0; i <= sh->st; i++)
    for (int k = 0; k < sh->layers; k++)
      for (int j = 0; j < sh->su; j++) {
        const float *fr = f->geom.frames + 9 * sector(sh, i, k, j);
        double v = sh->core + (1.0 - sh->core) * (k + 0.5) / sh->layers;
        double r = hypot(fr[0], fr[2]);
        assert_true(fabs(r - v) < 1e-5);
        assert_true(fabs(fr[1] - LENGTH * i / sh->st) < 1e-4);
        assert_true(fabs(fr[3] - fr[0] / r) < 1e-5);
        assert_true(fabs(fr[4]) < 1e-5);
        assert_true(fabs(fr[5] - fr[2] / r) < 1e-5);
        double tn = fr[3] * fr[6] + fr[4] * fr[7] + fr[5] * fr[8];
        assert_true(fabs(tn) < 1e-5);
        assert_true(fabs(fr[7]) < 1e-5);
        /* consecutive phases: the phase direction points to the next */
        const float *nx =
            f->geom.frames + 9 * sector(sh, i, k, (j + 1) % sh->su);
        double dx = nx[0] - fr[0], dz = nx[2] - fr[2];
        assert_true(dx * fr[6] + dz * fr[8] > 0.0);
      }
}

/* Azimuths are measured from the outward normal towards the phase
 * direction: an eye on the normal is at 0, on the phase direction at pi/2,
 * behind the sector at pi; a directional light likewise. */
static void test_sector_azimuths(void **state) {
  fixture *f = *state;
  const satf_shell_params *sh = &f->shell;
  size_t n = satf_shell_sector_count(sh);
  float *angles = malloc(2 * n * sizeof(float));
  assert_non_null(angles);
  const size_t s = sector(sh, 2, 1, 3);
  const float *fr = f->geom.frames + 9 * s;
  const struct {
    float eye_n, eye_t, light_n, light_t;
    double view, light;
  } cases[] = {{5, 0, 1, 0, 0.0, 0.0},
               {0, 5, 0, 1, PI / 2, PI / 2},
               {-5, 0, 1, -1, PI, 7 * PI / 4},
               {3, 3, -1, 1, PI / 4, 3 * PI / 4}};
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
    float eye[3], light[4] = {0, 0, 0, 0};
    for (int a = 0; a < 3; a++) {
      eye[a] = fr[a] + cases[c].eye_n * fr[3 + a] + cases[c].eye_t * fr[6 + a];
      light[a] = cases[c].light_n * fr[3 + a] + cases[c].light_t * fr[6 + a];
    }
    satf_maps_angles(&f->geom, eye, light, angles);
    assert_true(angles[2 * s] >= 0.0f && angles[2 * s] < 2 * PI + 1e-6);
    assert_true(circular_diff(angles[2 * s], cases[c].view) < 1e-5);
    assert_true(circular_diff(angles[2 * s + 1], cases[c].light) < 1e-5);
  }
  free(angles);
}

/* Features at fraction q of the database's range in every component. */
static void feature_at(const satf_db *db, float q, float out[3]) {
  float lo[3], hi[3];
  satf_db_feature_range(db, lo, hi);
  for (int a = 0; a < 3; a++)
    out[a] = lo[a] + q * (hi[a] - lo[a]);
}

/* An HSV whose two boundary sectors have identical parameters is uniform
 * (SATF eq. 6): one look-up swept along it, so rows 2i and 2i + 1 match. */
static void test_uniform_hsv_rows(void **state) {
  fixture *f = *state;
  const satf_shell_params *sh = &f->shell;
  size_t n = satf_shell_sector_count(sh);
  int w = satf_maps_width(f->maps);
  assert_int_equal(w, fixture_db_params().trace.width);
  float *angles = malloc(2 * n * sizeof(float));
  size_t layer = satf_maps_layer_texels(&f->geom, w);
  assert_int_equal(layer, (size_t)sh->su * w * 2 * sh->st);
  float *tex = calloc(layer * 4, sizeof(float));
  assert_non_null(angles);
  assert_non_null(tex);
  float feat[3];
  feature_at(f->db, 0.5f, feat);
  for (int i = 0; i <= sh->st; i++)
    for (int k = 0; k < sh->layers; k++)
      for (int j = 0; j < sh->su; j++) {
        size_t s = sector(sh, i, k, j);
        memcpy(f->geom.features + 3 * s, feat, sizeof feat);
        angles[2 * s] = 0.3f + 0.9f * (float)j;
        angles[2 * s + 1] = 1.0f + 0.2f * (float)k;
      }
  satf_map_options opt = satf_map_options_default();
  size_t row = (size_t)sh->su * w * 4;
  for (int k = 0; k < sh->layers; k++) {
    int lookups =
        satf_maps_build_layer(f->maps, &f->geom, angles, &opt, k, tex);
    assert_int_equal(lookups, sh->st * sh->su); /* one per HSV */
    for (int i = 0; i < sh->st; i++) {
      const float *r0 = tex + (size_t)(2 * i) * row;
      assert_memory_equal(r0, r0 + row, row * sizeof(float));
      /* the parameters do not change along t either */
      assert_memory_equal(r0, tex, row * sizeof(float));
    }
    /* each HSV's density channel is its mean density feature */
    for (size_t x = 0; x < layer; x++)
      assert_true(fabsf(tex[4 * x + 3] - feat[0]) <= 1e-6f * (1 + feat[0]));
  }
  free(angles);
  free(tex);
}

/* Record sample position of column x of an HSV seen head-on (theta_v = 0),
 * from trace.h's layout: the point at phase fraction (x + 1/2) / w on the
 * sector's outer arc, projected on the screen axis e = (0, 1), whose extent
 * over the sector is +-r_outer sin(span / 2). */
static double head_on_record_position(const satf_sector_shape *sh, int w,
                                      int x) {
  double f = (x + 0.5) / w, phi = (f - 0.5) * sh->phase_span;
  double half = 0.5 * sh->phase_span;
  double pe = sh->r_outer * sin(phi), ext = sh->r_outer * sin(half);
  return (pe + ext) / (2 * ext) * w - 0.5;
}

static double sample_record(const float *rec, int w, double xr) {
  if (xr < 0)
    xr = 0;
  if (xr > w - 1)
    xr = w - 1;
  int i0 = (int)floor(xr);
  if (i0 > w - 2)
    i0 = w - 2;
  double g = xr - i0;
  return rec[i0] + g * (rec[i0 + 1] - rec[i0]);
}

/* The mean re of the texels of a layer of sectors at `feature`, seen from
 * azimuth 0 and lit from `light`, where alpha > 0.05. */
static double layer_reflectance(fixture *f, const satf_maps *maps,
                                const float feature[3], float light) {
  const satf_shell_params *sh = &f->shell;
  size_t n = satf_shell_sector_count(sh);
  int w = satf_maps_width(maps);
  size_t layer = satf_maps_layer_texels(&f->geom, w);
  float *angles = calloc(2 * n, sizeof(float));
  float *tex = calloc(layer * 4, sizeof(float));
  float *kept = malloc(3 * n * sizeof(float)); /* the fixture's, restored */
  assert_non_null(angles);
  assert_non_null(tex);
  assert_non_null(kept);
  memcpy(kept, f->geom.features, 3 * n * sizeof(float));
  for (size_t s = 0; s < n; s++) {
    memcpy(f->geom.features + 3 * s, feature, 3 * sizeof(float));
    angles[2 * s + 1] = light;
  }
  satf_map_options opt = satf_map_options_default();
  satf_maps_build_layer(maps, &f->geom, angles, &opt, 0, tex);
  double sum = 0.0;
  int count = 0;
  for (size_t x = 0; x < layer; x++)
    if (tex[4 * x + 1] > 0.05f) {
      sum += tex[4 * x];
      count++;
    }
  memcpy(f->geom.features, kept, 3 * n * sizeof(float));
  free(kept);
  free(angles);
  free(tex);
  assert_true(count > 0);
  return sum / count;
}

/* re's scale is that of hair nothing shadows (maps.c, reflectance_scale):
 * the fixture database and its twin traced without in-sector shadows
 * (satf-build --no-shadow) get nearly the same scale; so shadowing in the
 * records only darkens: dense hair's re is at most the unshadowed twin's
 * (lit from the eye's side, across and from behind), sparse hair's about
 * equal. Before, each sample was scaled by its own mean over all light
 * azimuths, which its shadowing lowers: dense hair lit from the eye's side
 * came out brighter than hair nothing shadows (measured here: 1.10x the
 * twin's, and the imported ponytail 1.36x its strand reference). */
static void test_reflectance_scale_unshadowed(void **state) {
  fixture *f = *state;
  satf_build_params p = fixture_db_params();
  p.trace.self_shadow = 0;
  satf_db *flat = NULL;
  satf_maps *flat_maps = NULL;
  satf_error err;
  if (satf_build(&p, 0, NULL, NULL, &flat, &err) != SATF_OK ||
      satf_maps_create(flat, &flat_maps, &err) != SATF_OK)
    fail_msg("%s", err.message);
  double s = maps_reflectance_scale(f->maps);
  double s_flat = maps_reflectance_scale(flat_maps);
  printf("reflectance scale %.4f, traced without shadows %.4f\n", s, s_flat);
  assert_true(fabs(s / s_flat - 1.0) < 0.08);
  static const float density[2] = {0.9f, 0.02f};
  static const float light[3] = {0.0f, 0.5f * (float)PI, (float)PI};
  for (int q = 0; q < 2; q++)
    for (int l = 0; l < 3; l++) {
      float feat[3];
      feature_at(f->db, density[q], feat);
      double re = layer_reflectance(f, f->maps, feat, light[l]);
      double re_flat = layer_reflectance(f, flat_maps, feat, light[l]);
      printf("re at %.2f of the density range, light at %.2f pi: %.4f, "
             "traced without shadows %.4f (ratio %.3f)\n",
             (double)density[q], light[l] / PI, re, re_flat, re / re_flat);
      assert_true(re < 1.03 * re_flat);
      if (q == 1)
        assert_true(re > 0.75 * re_flat);
    }
  satf_maps_destroy(flat_maps);
  satf_db_destroy(flat);
}

/* What the row checks below work on: the sectors' azimuths, `layers`
 * layers of texels and one record's reflectance and alpha. */
typedef struct row_check {
  float *angles, *tex, *re, *al;
} row_check;

static row_check row_check_alloc(const fixture *f, int layers) {
  size_t n = satf_shell_sector_count(&f->shell);
  int w = satf_maps_width(f->maps);
  size_t layer = satf_maps_layer_texels(&f->geom, w);
  row_check c = {malloc(2 * n * sizeof(float)),
                 calloc(layer * 4 * (size_t)layers, sizeof(float)),
                 malloc((size_t)w * sizeof(float)),
                 malloc((size_t)w * sizeof(float))};
  assert_non_null(c.angles);
  assert_non_null(c.tex);
  assert_non_null(c.re);
  assert_non_null(c.al);
  return c;
}

static void row_check_free(row_check *c) {
  free(c->angles);
  free(c->tex);
  free(c->re);
  free(c->al);
}

/* The level of layer k's rows (stored reflectance weighted by alpha over
 * the row, per HSV j of row 0) into level[j]; 0 where nothing covers. */
static void row_levels(const float *t, int su, int w, double *level) {
  for (int j = 0; j < su; j++) {
    double ra = 0.0, a = 0.0;
    for (int x = 0; x < w; x++) {
      const float *texel = t + 4 * ((size_t)j * w + (size_t)x);
      ra += (double)texel[0] * texel[1];
      a += texel[1];
    }
    level[j] = a > 1e-6 ? ra / a : 0.0;
  }
}

/* With orientation_free (the default), every record keeps its structure
 * (stored reflectance over re / alpha the same across the row) but its
 * level is its samples' seen and lit from outside, whatever the sector's
 * azimuths: rows of one density under light azimuths from the sector's
 * outer side round to its inner side have one level, where the records'
 * own levels differ by far more (the in-sector shadowing that shaded each
 * cluster as a cylinder). */
static void test_orientation_free_level(void **state) {
  fixture *f = *state;
  const satf_shell_params *sh = &f->shell;
  size_t n = satf_shell_sector_count(sh);
  int w = satf_maps_width(f->maps);
  const satf_sector_shape *shape = &satf_db_params(f->db)->shape;
  row_check c = row_check_alloc(f, 1);
  float *angles = c.angles, *tex = c.tex, *re = c.re, *al = c.al;
  double *level = malloc((size_t)sh->su * sizeof(double));
  assert_non_null(level);
  float feat[3];
  feature_at(f->db, 0.8f, feat);
  for (size_t s = 0; s < n; s++) {
    memcpy(f->geom.features + 3 * s, feat, sizeof feat);
    int j = (int)(s % (size_t)sh->su);
    angles[2 * s] = 0.0f; /* head-on */
    angles[2 * s + 1] = SATF_TWO_PI_F * (float)j / (float)sh->su;
  }
  satf_map_options opt = satf_map_options_default();
  assert_int_equal(opt.orientation_free, 1);
  double lo = INFINITY, hi = 0.0;
  satf_maps_build_layer(f->maps, &f->geom, angles, &opt, 0, tex);
  row_levels(tex, sh->su, w, level);
  for (int j = 0; j < sh->su; j++) {
    assert_true(level[j] > 0.0);
    lo = fmin(lo, level[j]);
    hi = fmax(hi, level[j]);
    /* the structure: stored / (re / alpha) is one factor along the row */
    satf_db_lookup(f->db, feat, 0.0f, angles[2 * j + 1], opt.k_nearest, re, al);
    double q0 = 0.0;
    for (int x = 0; x < w; x++) {
      double xr = head_on_record_position(shape, w, x);
      double a = sample_record(al, w, xr), r = sample_record(re, w, xr);
      if (a < 0.05)
        continue;
      double q = tex[4 * ((size_t)j * w + (size_t)x)] / (r / a);
      if (q0 == 0.0)
        q0 = q;
      if (!(fabs(q - q0) <= 1e-3 * q0))
        fail_msg("HSV %d column %d: stored / record %.5f, the row's %.5f", j, x,
                 q, q0);
    }
  }
  printf("orientation-free levels over %d light azimuths: %.4f .. %.4f\n",
         sh->su, lo, hi);
  assert_true(hi - lo <= 1e-3 * hi);
  /* the records' own levels at the same parameters */
  opt.orientation_free = 0;
  satf_maps_build_layer(f->maps, &f->geom, angles, &opt, 0, tex);
  row_levels(tex, sh->su, w, level);
  lo = INFINITY, hi = 0.0;
  for (int j = 0; j < sh->su; j++) {
    lo = fmin(lo, level[j]);
    hi = fmax(hi, level[j]);
  }
  printf("the records' own levels: %.4f .. %.4f\n", lo, hi);
  assert_true(hi > 1.2 * lo);
  row_check_free(&c);
  free(level);
}

/* Top and bottom sectors of each HSV with clearly different densities: two
 * look-ups per HSV (shared with the neighbour along t), row 2i showing the
 * record at t_i and row 2i + 1 the one at t_{i+1} (SATF eq. 7). Checked
 * against satf_db_lookup directly, for a head-on view. Then the s-maps
 * (eq. 12) over the layers built. */
static void test_non_uniform_rows_and_shadow_sums(void **state) {
  fixture *f = *state;
  const satf_shell_params *sh = &f->shell;
  int w = satf_maps_width(f->maps);
  const satf_sector_shape *shape = &satf_db_params(f->db)->shape;
  size_t layer = satf_maps_layer_texels(&f->geom, w);
  row_check c = row_check_alloc(f, sh->layers);
  float *angles = c.angles, *tex = c.tex, *re = c.re, *al = c.al;
  float feat[2][3];
  feature_at(f->db, 0.2f, feat[0]);
  feature_at(f->db, 0.8f, feat[1]);
  for (int i = 0; i <= sh->st; i++)
    for (int k = 0; k < sh->layers; k++)
      for (int j = 0; j < sh->su; j++) {
        size_t s = sector(sh, i, k, j);
        memcpy(f->geom.features + 3 * s, feat[i % 2], sizeof feat[0]);
        angles[2 * s] = 0.0f; /* head-on */
        angles[2 * s + 1] = 0.5f + 0.3f * (float)j + 0.1f * (float)k;
      }
  satf_map_options opt = satf_map_options_default();
  opt.orientation_free = 0; /* the records' own level, laid as they are */
  size_t row = (size_t)sh->su * w * 4;
  /* stored reflectance / (re / alpha): the database's one scale (its value
   * is test_reflectance_scale_unshadowed's) */
  double scale = maps_reflectance_scale(f->maps);
  assert_true(scale > 1.0 && scale < 100.0);
  int alpha_seen = 0;
  for (int k = 0; k < sh->layers; k++) {
    float *t = tex + (size_t)k * layer * 4;
    int lookups = satf_maps_build_layer(f->maps, &f->geom, angles, &opt, k, t);
    assert_int_equal(lookups, sh->su * (sh->st + 1));
    for (int i = 0; i < sh->st; i++)
      for (int j = 0; j < sh->su; j++)
        for (int half = 0; half < 2; half++) {
          const float *fe = feat[(i + half) % 2];
          satf_db_lookup(f->db, fe, 0.0f, angles[2 * sector(sh, i, k, j) + 1],
                         opt.k_nearest, re, al);
          const float *texel =
              t + (size_t)(2 * i + half) * row + (size_t)j * w * 4;
          for (int x = 0; x < w; x++) {
            double xr = head_on_record_position(shape, w, x);
            double a = sample_record(al, w, xr), r = sample_record(re, w, xr);
            if (fabs(texel[4 * x + 1] - a) > 1e-5)
              fail_msg("layer %d HSV (%d, %d) row %d column %d: alpha %.7f, "
                       "direct look-up %.7f",
                       k, i, j, 2 * i + half, x, (double)texel[4 * x + 1], a);
            double dens = 0.5 * (feat[0][0] + feat[1][0]);
            assert_true(fabs(texel[4 * x + 3] - dens) <= 1e-5 * (1 + dens));
            if (a > 0.05) {
              double q = texel[4 * x] / (r / a), want = scale;
              if (!(fabs(q - want) <= 1e-3 * want))
                fail_msg("layer %d HSV (%d, %d) row %d column %d: "
                         "reflectance scaled by %.5f, expected %.5f",
                         k, i, j, 2 * i + half, x, q, want);
              alpha_seen++;
            }
          }
        }
  }
  assert_true(alpha_seen > 0);

  /* eq. 12: channel 2 of layer k sums the alpha of layers m > k */
  float *before = malloc(layer * 4 * (size_t)sh->layers * sizeof(float));
  assert_non_null(before);
  memcpy(before, tex, layer * 4 * (size_t)sh->layers * sizeof(float));
  satf_maps_shadow_sums(&f->geom, w, tex);
  for (size_t x = 0; x < layer; x++) {
    float sum = 0.0f;
    for (int k = sh->layers - 1; k >= 0; k--) {
      const float *p = tex + ((size_t)k * layer + x) * 4;
      const float *q = before + ((size_t)k * layer + x) * 4;
      assert_true(p[2] == sum); /* exactly; 0 for the outermost */
      assert_true(p[0] == q[0] && p[1] == q[1] && p[3] == q[3]);
      sum += p[1];
    }
  }
  free(before);
  row_check_free(&c);
}

/* The s-map sums again with alphas that are exact in binary (k/8), so the
 * sum is exact in any order: summed here from the innermost outwards. */
static void test_shadow_sums_exact(void **state) {
  fixture *f = *state;
  const satf_shell_params *sh = &f->shell;
  int w = 4;
  size_t layer = satf_maps_layer_texels(&f->geom, w);
  float *tex = calloc(layer * 4 * (size_t)sh->layers, sizeof(float));
  assert_non_null(tex);
  for (int k = 0; k < sh->layers; k++)
    for (size_t x = 0; x < layer; x++) {
      float *p = tex + ((size_t)k * layer + x) * 4;
      p[1] = (float)((x + 3 * (size_t)k) % 9) / 8.0f;
      p[2] = 123.0f; /* overwritten */
    }
  satf_maps_shadow_sums(&f->geom, w, tex);
  for (size_t x = 0; x < layer; x++)
    for (int k = 0; k < sh->layers; k++) {
      float sum = 0.0f;
      for (int m = k + 1; m < sh->layers; m++)
        sum += tex[((size_t)m * layer + x) * 4 + 1];
      assert_true(tex[((size_t)k * layer + x) * 4 + 2] == sum);
    }
  free(tex);
}

/* Uniformly placed Gaussian strands of peak 1/2 and sigma = width / 2 each
 * carry coverage pi sigma^2, so N of them in the unit disk (area pi) give a
 * mean density N (width / 2)^2 times the scale; the sectors' rho_st should
 * average to that away from the envelope, their centroids to the middle. */
static void test_uniform_density_features(void **state) {
  fixture *f = *state;
  satf_scene_density d;
  memset(&d, 0, sizeof d);
  d.type = SATF_SCENE_DENSITY_PROCEDURAL;
  d.strands = 4000;
  d.seed = 7;
  d.layout = SATF_SCENE_LAYOUT_UNIFORM;
  d.strand_width = 0.05f;
  d.scale = 1.5f;
  satf_strands *strands = NULL;
  satf_error err;
  assert_int_equal(satf_strands_create(&d, &strands, &err), SATF_OK);
  assert_int_equal(satf_strands_count(strands), 4000);
  satf_shell_params sh = {5, 4, 12, 0.2f};
  satf_shell_geom g;
  assert_int_equal(satf_shell_geom_create(f->cluster, &sh, &g, &err), SATF_OK);
  assert_int_equal(satf_sector_features(f->cluster, &sh, strands, NULL, NULL, 0,
                                        g.features, &err),
                   SATF_OK);
  double expected = 4000 * 0.025 * 0.025 * 1.5; /* 3.75 */
  double inner = 0, outer = 0, cs = 0, ct = 0;
  int n_inner = 0, n_outer = 0;
  for (int i = 0; i <= sh.st; i++)
    for (int k = 0; k < sh.layers; k++)
      for (int j = 0; j < sh.su; j++) {
        const float *fe = g.features + 3 * sector(&sh, i, k, j);
        if (k < sh.layers - 1) {
          inner += fe[0];
          cs += fe[1];
          ct += fe[2];
          n_inner++;
        } else {
          outer += fe[0];
          n_outer++;
        }
      }
  inner /= n_inner;
  outer /= n_outer;
  cs /= n_inner;
  ct /= n_inner;
  printf("mean rho_st: inner layers %.3f (expected %.3f), outermost %.3f; "
         "centroids %.3f %.3f\n",
         inner, expected, outer, cs, ct);
  assert_true(fabs(inner - expected) < 0.08 * expected);
  assert_true(fabs(cs - 0.5) < 0.03 && fabs(ct - 0.5) < 0.03);
  /* the outermost layer reaches the envelope, where coverage falls off */
  assert_true(outer < inner);
  satf_shell_geom_destroy(&g);
  satf_strands_destroy(strands);
}

/* Seams between neighbouring HSVs (maps.h, satf_maps_seams): a cluster of
 * procedural strands seen from the side, its maps built with one database
 * sample per look-up (k = 1) and with the default options. The default
 * must change the looked-up records less from one HSV to the next, along
 * the phase and along t (k = 1 showed visible jumps).
 * The jump across a boundary over the step inside an HSV is printed too:
 * the records' own profile across an HSV dominates it for any k. */
typedef struct seam_figures {
  double ratio_re, ratio_al;         /* jump across / step inside, phase */
  double hsv_re, hsv_al, t_re, t_al; /* mean |change| between HSVs */
} seam_figures;

static seam_figures seam_measure(const fixture *f, const satf_shell_geom *g,
                                 const satf_map_options *opt) {
  const satf_shell_params *sh = &g->shell;
  size_t n = satf_shell_sector_count(sh);
  int w = satf_maps_width(f->maps);
  size_t layer = satf_maps_layer_texels(g, w);
  float *angles = malloc(2 * n * sizeof(float));
  float *tex = calloc(layer * 4, sizeof(float));
  assert_non_null(angles);
  assert_non_null(tex);
  const float eye[3] = {24.0f, 6.0f, 9.0f};
  const float light[4] = {0.3f, 0.8f, 0.5f, 0.0f};
  satf_maps_angles(g, eye, light, angles);
  satf_maps_seams acc;
  memset(&acc, 0, sizeof acc);
  for (int k = 0; k < sh->layers; k++) {
    satf_maps_build_layer(f->maps, g, angles, opt, k, tex);
    satf_maps_seams_add(g, w, tex, &acc);
  }
  long texels = (long)sh->layers * 2 * sh->st * sh->su * w;
  assert_true(acc.n_al_edge == (long)sh->layers * 2 * sh->st * sh->su);
  assert_true(acc.n_al_hsv == texels);
  assert_true(acc.n_re_hsv > texels / 4 && acc.n_re_t > 0);
  seam_figures s;
  satf_maps_seams_ratio(&acc, &s.ratio_re, &s.ratio_al);
  s.hsv_re = acc.re_hsv / (double)acc.n_re_hsv;
  s.hsv_al = acc.al_hsv / (double)acc.n_al_hsv;
  s.t_re = acc.re_t / (double)acc.n_re_t;
  s.t_al = acc.al_t / (double)acc.n_al_t;
  free(angles);
  free(tex);
  return s;
}

/* Shells `sh` over the fixture's cluster holding 1500 clumped strands,
 * with their density features; *strands to destroy after. */
static void clumped_shells(const fixture *f, uint64_t seed, int clumps,
                           const satf_shell_params *sh, satf_shell_geom *g,
                           satf_strands **strands) {
  satf_scene_density d;
  memset(&d, 0, sizeof d);
  d.type = SATF_SCENE_DENSITY_PROCEDURAL;
  d.strands = 1500;
  d.seed = seed;
  d.layout = SATF_SCENE_LAYOUT_CLUMPED;
  d.clumps = clumps;
  d.clump_spread = 0.3f;
  d.strand_width = 0.03f;
  d.scale = 1.0f;
  satf_error err;
  assert_int_equal(satf_strands_create(&d, strands, &err), SATF_OK);
  assert_int_equal(satf_shell_geom_create(f->cluster, sh, g, &err), SATF_OK);
  assert_int_equal(satf_sector_features(f->cluster, sh, *strands, NULL, NULL, 0,
                                        g->features, &err),
                   SATF_OK);
}

static void test_default_lookup_reduces_seams(void **state) {
  fixture *f = *state;
  satf_shell_params sh = {4, 12, 16, 0.3f};
  satf_shell_geom g;
  satf_strands *strands = NULL;
  clumped_shells(f, 11, 6, &sh, &g, &strands);
  satf_map_options one = satf_map_options_default(), def = one;
  one.k_nearest = 1;
  seam_figures s1 = seam_measure(f, &g, &one);
  seam_figures sd = seam_measure(f, &g, &def);
  const seam_figures *s[2] = {&s1, &sd};
  for (int c = 0; c < 2; c++)
    printf("k = %d: HSV to HSV along the phase: reflectance %.4f, alpha "
           "%.4f; along t: %.4f, %.4f; jump across / step inside: %.2f, "
           "%.2f\n",
           c ? def.k_nearest : 1, s[c]->hsv_re, s[c]->hsv_al, s[c]->t_re,
           s[c]->t_al, s[c]->ratio_re, s[c]->ratio_al);
  assert_true(s1.hsv_re > 0.0 && s1.t_re > 0.0 && s1.t_al > 0.0);
  assert_true(sd.hsv_re < 0.9 * s1.hsv_re);
  assert_true(sd.hsv_al < s1.hsv_al);
  assert_true(sd.t_re < s1.t_re);
  assert_true(sd.t_al < s1.t_al);
  satf_shell_geom_destroy(&g);
  satf_strands_destroy(strands);
}

/* The maps from the neighbour cache (satf_maps_prepare: each look-up
 * blends neighbours found once, its records fetched one look-up ahead)
 * equal the maps whose every look-up searches the database (SATF eq. 4
 * as satf_db_lookup), over clumped hair with uniform and non-uniform HSVs
 * and oblique azimuths; and after the eye turns, looking up again only
 * what moved (satf_maps_update_layer) gives the full build's maps. */
static void test_cached_lookups_equal_searched(void **state) {
  fixture *f = *state;
  satf_shell_params sh = {3, 10, 12, 0.3f};
  satf_shell_geom g;
  satf_strands *strands = NULL;
  satf_error err;
  clumped_shells(f, 5, 5, &sh, &g, &strands);
  int w = satf_maps_width(f->maps);
  size_t n = satf_maps_layer_texels(&g, w) * 4 * (size_t)sh.layers;
  size_t layer = satf_maps_layer_texels(&g, w) * 4;
  size_t ns = satf_shell_sector_count(&sh);
  float *searched = calloc(n, sizeof(float)),
        *cached = calloc(n, sizeof(float));
  float *angles = malloc(2 * ns * sizeof(float));
  float *prev = malloc(2 * ns * sizeof(float));
  assert_non_null(searched);
  assert_non_null(cached);
  assert_non_null(angles);
  assert_non_null(prev);
  satf_map_options opt = satf_map_options_default();
  const float light[4] = {0.3f, 0.8f, -0.5f, 0.0f};
  float eye[3] = {6.0f, 4.0f, 7.0f};
  satf_maps_angles(&g, eye, light, angles);
  int lookups = 0;
  for (int k = 0; k < sh.layers; k++)
    lookups += satf_maps_build_layer(f->maps, &g, angles, &opt, k,
                                     searched + (size_t)k * layer);
  /* both kinds of HSV: one look-up (uniform) and two (shared along t) */
  printf("%d look-ups for %d HSVs\n", lookups, sh.st * sh.su * sh.layers);
  assert_true(lookups > sh.st * sh.su * sh.layers);
  int uniform = 0; /* a uniform HSV lays one record in both its rows */
  size_t row = (size_t)sh.su * (size_t)w * 4;
  for (int k = 0; k < sh.layers; k++)
    for (int i = 0; i < sh.st; i++)
      for (int j = 0; j < sh.su; j++) {
        const float *r0 = searched + (size_t)k * layer + 2 * (size_t)i * row +
                          (size_t)j * (size_t)w * 4;
        uniform += !memcmp(r0, r0 + row, (size_t)w * 4 * sizeof(float));
      }
  printf("%d uniform HSVs\n", uniform);
  assert_true(uniform > 0);
  assert_int_equal(satf_maps_prepare(f->maps, &g, &opt, &err), SATF_OK);
  for (int k = 0; k < sh.layers; k++)
    assert_int_equal(satf_maps_build_layer(f->maps, &g, angles, &opt, k,
                                           cached + (size_t)k * layer),
                     satf_maps_build_layer(f->maps, &g, angles, &opt, k,
                                           cached + (size_t)k * layer));
  for (size_t x = 0; x < n; x++)
    if (fabsf(cached[x] - searched[x]) > 1e-6f * (1.0f + fabsf(searched[x])))
      fail_msg("texel value %zu: %.8f from the cache, %.8f searched", x,
               (double)cached[x], (double)searched[x]);
  /* the eye turns: only HSVs whose azimuths moved are looked up again */
  memcpy(prev, angles, 2 * ns * sizeof(float));
  eye[0] = 6.5f;
  satf_maps_angles(&g, eye, light, angles);
  for (int k = 0; k < sh.layers; k++) {
    satf_maps_update_layer(f->maps, &g, angles, prev, &opt, k,
                           cached + (size_t)k * layer);
    satf_maps_build_layer(f->maps, &g, angles, &opt, k,
                          searched + (size_t)k * layer);
  }
  assert_memory_equal(cached, searched, n * sizeof(float));
  satf_neighbor_cache_free(g.neighbors);
  g.neighbors = NULL;
  satf_shell_geom_destroy(&g);
  satf_strands_destroy(strands);
  free(searched);
  free(cached);
  free(angles);
  free(prev);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_sector_frames),
      cmocka_unit_test(test_sector_azimuths),
      cmocka_unit_test(test_uniform_hsv_rows),
      cmocka_unit_test(test_non_uniform_rows_and_shadow_sums),
      cmocka_unit_test(test_reflectance_scale_unshadowed),
      cmocka_unit_test(test_shadow_sums_exact),
      cmocka_unit_test(test_uniform_density_features),
      cmocka_unit_test(test_default_lookup_reduces_seams),
      cmocka_unit_test(test_cached_lookups_equal_searched),
      cmocka_unit_test(test_orientation_free_level),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
