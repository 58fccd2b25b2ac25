/* test_vdb_clusters.c - clusters whose density is one VDB file (what
 * satf-import --vdb writes: every cluster names the same file and grid)
 * share one copy of its voxels, so the renderer's memory does not grow
 * with the clusters times the grid. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "render_fixture.h"
#include "satf/density.h"

enum { W = 64, H = 48, CLUSTERS = 48 };

FIXTURE_GL_GROUP(W, H)

/* Resident memory of this process in bytes (/proc/self/status VmRSS). */
static double rss_bytes(void) {
  FILE *f = fopen("/proc/self/status", "r");
  char line[256];
  double kb = -1.0;
  while (f && fgets(line, sizeof line, f))
    if (!strncmp(line, "VmRSS:", 6))
      kb = atof(line + 6);
  if (f)
    fclose(f);
  return kb * 1024.0;
}

/* A grid of about 1.3 million voxels (5 MB of floats): a thick tube along
 * the clusters' axis. */
static void write_tube_vdb(const char *path) {
  satf_vdb_builder *b = NULL;
  satf_error err;
  assert_int_equal(satf_vdb_builder_create(0.05f, &b, &err), SATF_OK);
  const float p0[3] = {0, -3, 0}, p1[3] = {0, 3, 0};
  assert_int_equal(satf_vdb_builder_add_tube(b, p0, p1, 0.45f, 1.0f, &err),
                   SATF_OK);
  assert_int_equal(satf_vdb_builder_write(b, path, "density", &err), SATF_OK);
  satf_vdb_builder_destroy(b);
}

static void test_share_outlives_original(void **state) {
  (void)state;
  char path[1024];
  const char *dir = getenv("SATF_TEST_TMP");
  snprintf(path, sizeof path, "%s/vdb_share.vdb", dir ? dir : ".");
  write_tube_vdb(path);
  satf_vdb_grid *g = NULL;
  satf_error err;
  assert_int_equal(satf_vdb_read(path, "density", &g, &err), SATF_OK);
  const float at[3] = {0.1f, 0.5f, 0.0f};
  float v = satf_vdb_sample(g, at);
  assert_true(v > 0.0f);
  satf_vdb_grid *s = satf_vdb_grid_share(g);
  assert_non_null(s);
  satf_vdb_grid_destroy(g);
  assert_float_equal(satf_vdb_sample(s, at), v, 0.0f);
  satf_vdb_grid_destroy(s);
  assert_null(satf_vdb_grid_share(NULL));
}

static void test_clusters_share_one_grid(void **state) {
  fixture_gl *f = *state;
  char path[1024];
  const char *dir = getenv("SATF_TEST_TMP");
  snprintf(path, sizeof path, "%s/vdb_clusters.vdb", dir ? dir : ".");
  write_tube_vdb(path);
  long long file = satf_file_size(path);
  assert_true(file > 0);

  size_t cap = 4096 + (size_t)CLUSTERS * (400 + strlen(path));
  char *json = malloc(cap);
  assert_non_null(json);
  size_t n = (size_t)snprintf(json, cap, "{\"macro_clusters\": [");
  for (int i = 0; i < CLUSTERS; i++)
    n += (size_t)snprintf(
        json + n, cap - n,
        "%s{\"prototype\": {\"trajectory\": [[0, -3, 0], [0, 3, 0]], "
        "\"a\": 0.4, \"b\": 0.4, \"shell\": {\"layers\": 1, \"st\": 4, "
        "\"su\": 4}, \"density\": {\"type\": \"vdb\", \"file\": \"%s\"}}, "
        "\"instances\": [{\"translate\": [%d, 0, 0]}]}",
        i ? ", " : "", path, i % 8 - 4);
  snprintf(json + n, cap - n,
           "], \"camera\": {\"position\": [0, 0, 30], \"target\": [0, 0, 0], "
           "\"fov_y\": 0.8}, \"lights\": [{\"direction\": [0, 0, -1]}], "
           "\"image\": {\"width\": %d, \"height\": %d}}",
           W, H);
  satf_scene *scene = fixture_scene(json);
  free(json);
  assert_non_null(scene);

  double before = rss_bytes();
  satf_renderer *r = fixture_renderer(scene, f->db, W, H, 1);
  assert_non_null(r);
  double grown = rss_bytes() - before;
  printf("%d clusters naming one %.1f MB VDB: the renderer took %.1f MB\n",
         CLUSTERS, (double)file / 1e6, grown / 1e6);
  /* a copy per cluster took CLUSTERS times the grid's voxels (5 MB each,
   * 240 MB); the renderer's own programs, maps and arrays take about 37 MB
   * (60 MB under AddressSanitizer), so the bound is half the copies' */
  assert_true(grown < 120e6);
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_share_outlives_original),
      cmocka_unit_test(test_clusters_share_one_grid),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
