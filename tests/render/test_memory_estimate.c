/* test_memory_estimate.c - satf_render_memory_estimate counts what the
 * GPU's maps keep (--maps gpu) and the database, from the database's
 * dimensions as the public satf_db API gives them: the GPU's estimate
 * exceeds the CPU's by at least the records as halfs, and by exactly their
 * growth when the database grows; the physical shading counts the
 * re-levelled copy at the hair's absorption levels; the sparse-strands
 * setting decides which clusters count as shells; the strand path counts
 * its points. No GL. */
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

#include "render_fixture.h"

/* Two procedural prototypes (drawn as clusters, with maps), one of them
 * instanced twice; `material` is the scene's "material" object. */
static satf_scene *scene_with(const char *material) {
  char json[2048];
  snprintf(
      json, sizeof json,
      "{\"macro_clusters\": ["
      " {\"prototype\": {\"trajectory\": [[0, -2, 0], [0, 2, 0]], \"a\": 0.5,"
      "   \"shell\": {\"layers\": 3, \"st\": 6, \"su\": 6},"
      "   \"density\": {\"strands\": 80, \"seed\": 3}},"
      "  \"instances\": [{\"translate\": [-1, 0, 0]},"
      "                  {\"translate\": [1, 0, 0]}]},"
      " {\"prototype\": {\"trajectory\": [[0, -1, 0], [0, 1, 0]], \"a\": 0.4,"
      "   \"shell\": {\"layers\": 2, \"st\": 4, \"su\": 8},"
      "   \"density\": {\"strands\": 60, \"seed\": 5}}}],"
      " \"material\": %s}",
      material);
  satf_scene *s = fixture_scene(json);
  assert_non_null(s);
  return s;
}

/* An empty database of these dimensions (fibre records when fiber): the
 * estimate reads its dimensions only, so nothing is traced. */
static satf_db *empty_db(int fiber, int samples, int n_view, int width) {
  satf_build_params p =
      fiber ? satf_build_params_default_fiber() : satf_build_params_default();
  p.samples = samples;
  p.n_view = p.n_light = n_view;
  p.trace.width = width;
  satf_db *db = NULL;
  satf_error err;
  if (satf_db_create(&p, &db, &err) != SATF_OK)
    fail_msg("%s", err.message);
  return db;
}

/* Records of db times the values each: samples x view x light azimuths. */
static double records(const satf_db *db) {
  const satf_build_params *p = satf_db_params(db);
  return (double)p->samples * p->n_view * p->n_light;
}

static void estimate(const satf_scene *scene, const satf_db *db,
                     satf_maps_mode maps, satf_render_memory *m) {
  satf_render_memory_options opt = satf_render_memory_options_default();
  opt.width = 320;
  opt.height = 240;
  opt.db = db;
  opt.maps = maps;
  double total = satf_render_memory_estimate(scene, &opt, m);
  assert_true(total == m->total);
  assert_true(m->total > 0.0);
}

/* What the GPU's maps add: GPU's estimate less the CPU's, every other
 * part the same. */
static double gpu_extra(const satf_scene *scene, const satf_db *db) {
  satf_render_memory cpu, gpu;
  estimate(scene, db, SATF_MAPS_CPU, &cpu);
  estimate(scene, db, SATF_MAPS_GPU, &gpu);
  assert_true(cpu.gpu_maps == 0.0);
  assert_true(gpu.hsvs == cpu.hsvs && gpu.strands == cpu.strands &&
              gpu.pixels == cpu.pixels && gpu.database == cpu.database &&
              gpu.fixed == cpu.fixed);
  assert_true(fabs(gpu.total - cpu.total - gpu.gpu_maps) < 1.0);
  return gpu.total - cpu.total;
}

static void test_kk(void **st) {
  (void)st;
  satf_scene *scene = scene_with("{\"model\": \"kk\"}");
  satf_db *small = empty_db(0, 64, 16, 32), *big = empty_db(0, 128, 16, 32);
  /* the database as read: reflectance and alpha, floats and halfs */
  satf_render_memory m;
  estimate(scene, small, SATF_MAPS_CPU, &m);
  assert_true(m.database == records(small) * 2 * 32 * 1.5 * sizeof(float));
  /* 700 bytes per HSV of a prototype (108 of 3 x 6 x 6, 64 of 2 x 4 x 8),
   * 60,000 per instance (3) and each instance's maps: records 32 samples wide,
   * a quad of halfs (8 bytes) a texel, 2 x 32 texels an HSV in the CPU's copy
   * and su x 32 around by 2 x st rows (st up to a multiple of 4) a layer in GL:
   * the first's (108 x 64 + 3 x 6 x 32 x 16) x 8 = 129,024 twice, the second's
   * (64 x 64 + 2 x 8 x 32 x 8) x 8 = 65,536 */
  double maps = 2 * 129024.0 + 65536.0;
  assert_true(fabs(m.hsvs - (700.0 * (108 + 64) + 3 * 60e3 + maps)) < 1.0);
  /* the GPU keeps every record's reflectance and alpha as halfs */
  double halfs_small = records(small) * 2 * 32 * 2;
  double extra_small = gpu_extra(scene, small);
  assert_true(extra_small >= halfs_small);
  /* 64 more samples: their records' halfs, and a level (one float) each
   * in the table the records' look-up scales by (maps_sample_levels) */
  double halfs_big = records(big) * 2 * 32 * 2;
  double grown = gpu_extra(scene, big) - extra_small;
  assert_true(fabs(grown - (halfs_big - halfs_small + 64 * sizeof(float))) <
              1.0);
  /* without the database neither it, the maps nor the GPU's maps are
   * counted */
  satf_render_memory_options none = satf_render_memory_options_default();
  none.width = 320;
  none.height = 240;
  none.maps = SATF_MAPS_GPU;
  satf_render_memory without;
  satf_render_memory_estimate(scene, &none, &without);
  assert_true(without.database == 0.0 && without.gpu_maps == 0.0);
  assert_true(fabs(m.total - m.database - maps - without.total) < 1.0);
  satf_db_destroy(small);
  satf_db_destroy(big);
  satf_scene_destroy(scene);
}

/* The physical shading: the fibre database as read plus its copy
 * re-levelled at the hair's absorption (one level for a grey absorption,
 * three for three distinct values: 3 + 3 levels channels,
 * SATF_DB_FIBER_CHANNELS), which the GPU keeps as halfs. */
static void test_physical(void **st) {
  (void)st;
  satf_scene *grey =
      scene_with("{\"model\": \"physical\", \"absorption\": [0.5, 0.5, 0.5]}");
  satf_scene *brown =
      scene_with("{\"model\": \"physical\", \"absorption\": [0.2, 1.0, 4.0]}");
  satf_db *db = empty_db(1, 32, 12, 16);
  int channels = satf_db_channels(db);
  assert_int_equal(channels, SATF_DB_FIBER_CHANNELS(5)); /* default levels */
  satf_render_memory g, b;
  estimate(grey, db, SATF_MAPS_CPU, &g);
  estimate(brown, db, SATF_MAPS_CPU, &b);
  double floats = records(db) * 16 * sizeof(float); /* a channel's */
  /* the copy's 6 more channels (floats and halfs), and 6 more floats per
   * sample and view azimuth in its orientation-free levels (maps_fiber.c:
   * rel_levels) */
  assert_true(g.database >= floats * (channels + 6));
  assert_true(fabs(b.database - g.database -
                   (floats * 6 * 1.5 + 32.0 * 12 * 6 * sizeof(float))) < 1.0);
  double halfs = records(db) * 16 * 2; /* a channel's */
  double grey_extra = gpu_extra(grey, db);
  assert_true(grey_extra >= halfs * 6);
  assert_true(fabs(gpu_extra(brown, db) - grey_extra -
                   (halfs * 6 + 32.0 * 12 * 6 * sizeof(float))) < 1.0);
  /* a Phong database cannot be shaded physically: only its records */
  satf_db *phong = empty_db(0, 32, 12, 16);
  estimate(grey, phong, SATF_MAPS_CPU, &g);
  assert_true(g.database == records(phong) * 2 * 16 * 1.5 * sizeof(float));
  satf_db_destroy(phong);
  satf_db_destroy(db);
  satf_scene_destroy(grey);
  satf_scene_destroy(brown);
}

/* A procedural prototype and a cluster of `strands` strands of its own
 * (tracks, st rows), drawn as strands at the default sparse-strands
 * setting when it holds at most 8 of them. */
static satf_scene *sparse_scene(int strands, int st) {
  char json[4096], tracks[2048] = "";
  size_t at = 0;
  for (int k = 0; k < strands; k++)
    at += (size_t)snprintf(tracks + at, sizeof tracks - at,
                           "%s[0, %g, 0, %g, 0, %g, 0]", k ? ", " : "", 0.1 * k,
                           0.1 * k, 0.1 * k);
  snprintf(json, sizeof json,
           "{\"macro_clusters\": ["
           " {\"prototype\": {\"trajectory\": [[0, -2, 0], [0, 2, 0]],"
           "   \"a\": 0.5, \"shell\": {\"layers\": 3, \"st\": 6, \"su\": 6},"
           "   \"density\": {\"strands\": 80, \"seed\": 3}}},"
           " {\"prototype\": {\"trajectory\": [[2, -2, 0], [2, 2, 0]],"
           "   \"a\": 0.5, \"shell\": {\"layers\": 3, \"st\": %d, \"su\": 8},"
           "   \"density\": {\"type\": \"tracks\", \"slices\": 3,"
           "     \"strand_width\": 0.1, \"tracks\": [%s]}}}]}",
           st, tracks);
  satf_scene *s = fixture_scene(json);
  assert_non_null(s);
  return s;
}

/* The estimate at sparse-strands setting `sparse` with `points` source
 * strand points drawn (--strands; 0: the clusters), with the GPU's maps
 * where db is given. */
static satf_render_memory estimate_at(const satf_scene *scene,
                                      const satf_db *db, int sparse,
                                      size_t points) {
  satf_render_memory_options o = satf_render_memory_options_default();
  o.db = db;
  o.maps = db ? SATF_MAPS_GPU : SATF_MAPS_CPU;
  o.sparse_strands = sparse;
  o.strand_points = points;
  satf_render_memory m;
  satf_render_memory_estimate(scene, &o, &m);
  return m;
}

/* The HSVs' and the GPU's maps' parts at sparse-strands setting `sparse`. */
static satf_render_memory at_setting(const satf_scene *scene, const satf_db *db,
                                     int sparse) {
  return estimate_at(scene, db, sparse, 0);
}

/* The sparse-strands setting moves the estimate as it moves the
 * renderer: a cluster of 3 strands, drawn as strands by default and at
 * the largest setting, takes maps and the full rate of its HSVs at 0
 * (every cluster drawn as shells), in proportion to its HSVs; settings
 * past the range count as its ends. */
static void test_sparse_setting(void **st) {
  (void)st;
  satf_db *db = empty_db(0, 32, 8, 16);
  satf_scene *a = sparse_scene(3, 4), *b = sparse_scene(3, 12);
  satf_render_memory a_def = at_setting(a, db, SATF_SPARSE_STRANDS_DEFAULT);
  satf_render_memory a_max = at_setting(a, db, SATF_SPARSE_STRANDS_MAX);
  satf_render_memory a_all = at_setting(a, db, 0);
  satf_render_memory b_def = at_setting(b, db, SATF_SPARSE_STRANDS_DEFAULT);
  satf_render_memory b_all = at_setting(b, db, 0);
  assert_true(a_def.total == a_max.total);
  /* its maps: the GPU's sectors and neighbours, less the CPU's copy of
   * them that the HSVs' rate holds */
  assert_true(a_all.hsvs > a_def.hsvs && a_all.gpu_maps != a_def.gpu_maps &&
              a_all.total > a_def.total);
  assert_true(at_setting(a, db, -5).total == a_all.total);
  assert_true(at_setting(a, db, 1 << 20).total == a_max.total);
  /* the cluster's HSVs (3 layers x su 8 x st) and its strands' 9 points
   * (650 bytes each drawn as strands) are all that changes: as shells 700
   * bytes an HSV and its maps, records 16 samples wide, 2 x 16 texels of 8
   * bytes in the CPU's copy and as many in GL (st a multiple of 4), where
   * drawn as strands 320 */
  double points = 9 * 650.0;
  double per_a = (a_all.hsvs - a_def.hsvs + points) / (3.0 * 8 * 4);
  double per_b = (b_all.hsvs - b_def.hsvs + points) / (3.0 * 8 * 12);
  printf("a cluster drawn as shells instead of strands: %.0f bytes more "
         "per HSV (st 4), %.0f (st 12)\n",
         per_a, per_b);
  assert_true(fabs(per_a - (700.0 + 2 * 256 - 320)) < 1e-6 * per_a);
  assert_true(fabs(per_b - per_a) < 1e-6 * per_a);
  /* the default import's 8: more strands, drawn as shells at either */
  satf_scene *c = sparse_scene(9, 4);
  assert_true(at_setting(c, db, SATF_SPARSE_STRANDS_DEFAULT).total ==
              at_setting(c, db, 0).total);
  satf_scene_destroy(a);
  satf_scene_destroy(b);
  satf_scene_destroy(c);
  satf_db_destroy(db);
}

/* The estimate with `points` source strand points drawn (--strands). */
static satf_render_memory with_strands(const satf_scene *scene, size_t points) {
  return estimate_at(scene, NULL, SATF_SPARSE_STRANDS_DEFAULT, points);
}

/* The strand path (satf_renderer_set_strands) counts its points, 710
 * bytes each, plus its programs and buffers (90 MB) where no cluster is
 * drawn as its strands already; the clusters' parts stay as they are
 * (satf-view switches between the two). */
static void test_strand_path(void **st) {
  (void)st;
  satf_scene *a = scene_with("{}"), *b = sparse_scene(3, 4);
  satf_render_memory a0 = with_strands(a, 0), a1 = with_strands(a, 1000000);
  satf_render_memory b0 = with_strands(b, 0), b1 = with_strands(b, 1000000);
  printf("the strand path of 1M points: %.1f MB (%.1f with a cluster drawn "
         "as strands)\n",
         a1.strand_path / 1e6, b1.strand_path / 1e6);
  assert_true(a0.strand_path == 0.0 && b0.strand_path == 0.0);
  assert_float_equal(a1.strand_path, 710e6 + 90e6, 1.0);
  assert_float_equal(b1.strand_path, 710e6, 1.0);
  assert_true(a1.hsvs == a0.hsvs && b1.hsvs == b0.hsvs);
  assert_float_equal(a1.total - a0.total, a1.strand_path, 1.0);
  assert_string_equal(satf_render_memory_largest(&a1), "the strand path");
  assert_string_equal(satf_render_memory_largest(&a0), "pixels");
  satf_scene_destroy(a);
  satf_scene_destroy(b);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_kk),
      cmocka_unit_test(test_physical),
      cmocka_unit_test(test_sparse_setting),
      cmocka_unit_test(test_strand_path),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
