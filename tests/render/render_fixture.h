/* render_fixture.h - what the online renderer's tests share: a small HRIR
 * database built in memory, scenes parsed from JSON strings, a headless GL
 * context, and comparisons of rendered images. Header-only; each test
 * includes it once. */
#ifndef SATF_TESTS_RENDER_FIXTURE_H
#define SATF_TESTS_RENDER_FIXTURE_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "satf/db.h"
#include "satf/gl.h"
#include "satf/offline.h"
#include "satf/render.h"
#include "satf/scene.h"

/* A database small enough to build in a fraction of a second yet with
 * every kind of sector: 48 samples, 12 x 12 azimuths, records of 16. */
static inline satf_build_params fixture_db_params(void) {
  satf_build_params p = satf_build_params_default();
  p.samples = 48;
  p.n_view = 12;
  p.n_light = 12;
  p.grid = 12;
  p.trace.width = 16;
  return p;
}

static inline satf_db *fixture_db(void) {
  satf_build_params p = fixture_db_params();
  satf_db *db = NULL;
  satf_error err;
  if (satf_build(&p, 0, NULL, NULL, &db, &err) != SATF_OK) {
    fprintf(stderr, "fixture database: %s\n", err.message);
    return NULL;
  }
  return db;
}

/* Two prototypes, three instances (one turned), several layers: maps of
 * every kind in a fraction of a second. */
#define FIXTURE_TWO_PROTOTYPES                                                 \
  "{\"macro_clusters\": ["                                                     \
  " {\"prototype\": {\"trajectory\": [[0, -2, 0], [0.3, 0, 0], [0, 2, 0]],"    \
  "   \"a\": 0.5, \"shell\": {\"layers\": 3, \"st\": 6, \"su\": 6},"           \
  "   \"density\": {\"strands\": 80, \"seed\": 3}},"                           \
  "  \"instances\": [{\"translate\": [-1.2, 0, 0]},"                           \
  "   {\"translate\": [1.2, 0, -0.5],"                                         \
  "    \"rotate\": {\"axis\": [0, 1, 0], \"angle\": 40}}]},"                   \
  " {\"prototype\": {\"trajectory\": [[0, -1.5, 0], [0, 1.5, 0]],"             \
  "   \"a\": 0.4, \"shell\": {\"layers\": 2, \"st\": 4, \"su\": 8},"           \
  "   \"density\": {\"strands\": 60, \"seed\": 5}},"                           \
  "  \"instances\": [{\"translate\": [0, 0, 1]}]}],"                           \
  " \"camera\": {\"position\": [0, 1, 14], \"target\": [0, 0, 0],"             \
  "            \"fov_y\": 35},"                                                \
  " \"lights\": [{\"direction\": [-0.5, -0.6, -0.6]}],"                        \
  " \"background\": [0, 0, 0]}"

/* A fibre database small enough for a test (seconds): 24 sectors, 12 x 12
 * azimuths, records of `width` samples; NULL, and a message, on failure. */
static inline satf_db *fixture_fiber_db_width(int width) {
  satf_build_params p = satf_build_params_default_fiber();
  p.samples = 24;
  p.n_view = p.n_light = 12;
  p.grid = 12;
  p.trace.width = width;
  p.fiber.sub_rays = 4;
  satf_db *db = NULL;
  satf_error err;
  if (satf_build(&p, 0, NULL, NULL, &db, &err) != SATF_OK) {
    fprintf(stderr, "fibre database: %s\n", err.message);
    return NULL;
  }
  return db;
}
/* fixture_fiber_db_width of records of 16 samples. */
static inline satf_db *fixture_fiber_db(void) {
  return fixture_fiber_db_width(16);
}

/* A headless GL context of w x h and the fixture database: what a cmocka
 * group setup of a rendering test makes (free with fixture_gl_free). */
typedef struct fixture_gl {
  satf_gl_context *ctx;
  satf_db *db;
} fixture_gl;

static inline fixture_gl *fixture_gl_create(int w, int h) {
  fixture_gl *f = calloc(1, sizeof *f);
  satf_error err;
  if (!f)
    return NULL;
  if (satf_gl_context_create_headless(w, h, &f->ctx, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    free(f);
    return NULL;
  }
  if (!(f->db = fixture_db())) {
    satf_gl_context_destroy(f->ctx);
    free(f);
    return NULL;
  }
  return f;
}

static inline void fixture_gl_free(fixture_gl *f) {
  if (!f)
    return;
  satf_db_destroy(f->db);
  satf_gl_context_destroy(f->ctx);
  free(f);
}

/* Defines a test's cmocka group setup and teardown, `setup` making a
 * w x h fixture_gl in *state and `teardown` freeing it. */
#define FIXTURE_GL_GROUP(w, h)                                                 \
  static int setup(void **state) {                                             \
    *state = fixture_gl_create(w, h);                                          \
    return *state ? 0 : -1;                                                    \
  }                                                                            \
  static int teardown(void **state) {                                          \
    fixture_gl_free(*state);                                                   \
    return 0;                                                                  \
  }

/* The same for the physical mode's tests: file-scope `gl` (a w x h
 * fixture_gl) and `fiber_db` (fixture_fiber_db), made by `setup` and
 * freed by `teardown`. */
#define FIXTURE_FIBER_GROUP(w, h)                                              \
  static fixture_gl *gl;                                                       \
  static satf_db *fiber_db;                                                    \
  static int setup(void **state) {                                             \
    (void)state;                                                               \
    if (!(gl = fixture_gl_create(w, h)))                                       \
      return -1;                                                               \
    if ((fiber_db = fixture_fiber_db()))                                       \
      return 0;                                                                \
    fixture_gl_free(gl); /* teardown does not run after a failed setup */      \
    return -1;                                                                 \
  }                                                                            \
  static int teardown(void **state) {                                          \
    (void)state;                                                               \
    satf_db_destroy(fiber_db);                                                 \
    fixture_gl_free(gl);                                                       \
    return 0;                                                                  \
  }

/* Renders a beauty frame; returns its look-ups, -1 on failure. */
static inline long fixture_render_lookups(satf_renderer *r) {
  satf_frame_timing t;
  satf_error err;
  if (satf_renderer_render(r, SATF_AOV_BEAUTY, &t, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return -1;
  }
  return t.lookups;
}

/* A beauty image of the next frame (NULL, and a message, on failure). */
static inline satf_image *fixture_render_image(satf_renderer *r) {
  satf_image *img = NULL;
  satf_error err;
  if (satf_renderer_render_image(r, 0, &img, NULL, &err) != SATF_OK)
    fprintf(stderr, "%s\n", err.message);
  return img;
}

static inline satf_scene *fixture_scene(const char *json) {
  satf_scene *s = NULL;
  satf_error err;
  if (satf_scene_parse(json, strlen(json), "fixture.json", &s, &err) !=
      SATF_OK) {
    fprintf(stderr, "fixture scene: %s\n", err.message);
    return NULL;
  }
  return s;
}

/* A w x h renderer of `scene` with database db and `threads` map threads
 * (0: every core), or NULL (and a message). */
static inline satf_renderer *fixture_renderer(const satf_scene *scene,
                                              const satf_db *db, int w, int h,
                                              int threads) {
  satf_renderer *r = NULL;
  satf_error err;
  if (satf_renderer_create(scene, db, w, h, threads, &r, &err) != SATF_OK) {
    fprintf(stderr, "fixture renderer: %s\n", err.message);
    return NULL;
  }
  return r;
}

/* fixture_renderer with the CPU's maps (satf_renderer_set_maps), for the
 * tests that read an instance's CPU copy of its maps (in->texels), which
 * the GPU's maps, auto's choice on a hardware GPU, never fill. */
static inline satf_renderer *fixture_renderer_cpu_maps(const satf_scene *scene,
                                                       const satf_db *db, int w,
                                                       int h, int threads) {
  satf_renderer *r = fixture_renderer(scene, db, w, h, threads);
  satf_error err;
  if (r && satf_renderer_set_maps(r, SATF_MAPS_CPU, &err) != SATF_OK) {
    fprintf(stderr, "fixture renderer: %s\n", err.message);
    satf_renderer_destroy(r);
    return NULL;
  }
  return r;
}

/* The plane of `name`, or NULL (and a message) when the image lacks it. */
static inline const float *fixture_plane(const satf_image *img,
                                         const char *name) {
  int c = satf_image_channel_index(img, name);
  if (c < 0) {
    fprintf(stderr, "image has no channel %s\n", name);
    return NULL;
  }
  return satf_image_const_plane(img, c);
}

/* Largest |a - b| over the named channel of two images of equal size. */
static inline double fixture_max_diff(const satf_image *a, const satf_image *b,
                                      const char *name) {
  const float *pa = fixture_plane(a, name), *pb = fixture_plane(b, name);
  if (!pa || !pb)
    return INFINITY;
  size_t n = (size_t)satf_image_width(a) * (size_t)satf_image_height(a);
  double m = 0.0;
  for (size_t i = 0; i < n; i++) {
    double d = fabs((double)pa[i] - (double)pb[i]);
    if (!(d <= m)) /* NaN propagates as a failure */
      m = d;
  }
  return m;
}

/* 1 when the named channel of both images is identical bit for bit. */
static inline int fixture_same_bits(const satf_image *a, const satf_image *b,
                                    const char *name) {
  const float *pa = fixture_plane(a, name), *pb = fixture_plane(b, name);
  if (!pa || !pb)
    return 0;
  size_t n = (size_t)satf_image_width(a) * (size_t)satf_image_height(a);
  return memcmp(pa, pb, n * sizeof(float)) == 0;
}

/* A straight cluster of "tracks" hanging from y = 3 (t = 0) to y = -3,
 * seen from far away along z, whose strands all start at slice 1 of 9
 * (satf-import's clusters begin a little above their roots), cluster
 * shadows off; `material` is "" or the scene's material object. The JSON,
 * malloc'ed, or NULL. */
static inline char *fixture_rooted_tracks_json(const char *material) {
  enum { SLICES = 9, STRANDS = 600 };
  size_t cap = 256 * 1024; /* 600 tracks of 8 points: about 90 KB */
  char *json = malloc(cap);
  if (!json)
    return NULL;
  int n = snprintf(
      json, cap,
      "{\"macro_clusters\": [{\"prototype\": {"
      " \"trajectory\": [[0, 3, 0], [0, -3, 0]], \"a\": 1.0,"
      " \"shell\": {\"layers\": 3, \"st\": 8, \"su\": 12, \"core\": 0.2},"
      " \"density\": {\"type\": \"tracks\", \"slices\": %d,"
      " \"strand_width\": 0.06, \"tracks\": [",
      SLICES);
  satf_rng rng;
  satf_rng_seed(&rng, 12345u, 0u);
  for (int k = 0; k < STRANDS; k++) {
    float xy[2];
    do { /* a point of the unit disc */
      for (int c = 0; c < 2; c++)
        xy[c] = (float)satf_rng_range(&rng, -1.0, 1.0);
    } while (xy[0] * xy[0] + xy[1] * xy[1] > 0.9f);
    n += snprintf(json + n, cap - (size_t)n, "%s[1", k ? "," : "");
    for (int i = 1; i < SLICES; i++)
      n += snprintf(json + n, cap - (size_t)n, ", %.4f, %.4f", xy[0], xy[1]);
    n += snprintf(json + n, cap - (size_t)n, "]");
  }
  snprintf(json + n, cap - (size_t)n,
           "]}}}], \"camera\": {\"position\": [0, 0, 300], \"target\": [0, 0, "
           "0], \"fov_y\": 1.6}, \"lights\": [{\"direction\": [-0.3, -0.2, "
           "-0.9]}], \"effects\": {\"cluster_shadows\": false},"
           " \"background\": [0, 0, 0]%s%s}",
           material[0] ? ", \"material\": " : "", material);
  return json;
}

/* Of a frame of fixture_rooted_tracks_json: the least luminance per unit
 * alpha of the first six image rows the hair covers (A > 0.5 in ten
 * pixels or more) over that of the rows of its middle third; -1 when the
 * hair's top is not in the upper third. */
static inline double fixture_root_rows_ratio(const satf_image *img) {
  int w = satf_image_width(img), h = satf_image_height(img);
  const float *A = fixture_plane(img, "A"), *R = fixture_plane(img, "R"),
              *G = fixture_plane(img, "G"), *B = fixture_plane(img, "B");
  if (!A || !R || !G || !B)
    return -1.0;
  double body = 0.0, lo = INFINITY;
  int first = -1, rows = 0;
  for (int y = 0; y < h; y++) {
    double l = 0.0, a = 0.0;
    int c = 0;
    for (int x = 0; x < w; x++) {
      size_t i = (size_t)y * (size_t)w + (size_t)x;
      if (A[i] > 0.5f)
        l += 0.2126 * R[i] + 0.7152 * G[i] + 0.0722 * B[i], a += A[i], c++;
    }
    if (c < 10)
      continue;
    if (first < 0)
      first = y;
    if (y < first + 6)
      lo = fmin(lo, l / a);
    if (y >= h / 3 && y < 2 * h / 3)
      body += l / a, rows++;
  }
  if (first <= 0 || first >= h / 3 || rows == 0 || !(body > 0.0))
    return -1.0;
  return lo / (body / rows);
}

#ifdef SATF_TOOLS_COMPARE_METRICS_H
/* img's R, G, B and A as satf-compare's image (metrics.h, included before
 * this header by the tests that measure frames). */
static inline compare_image fixture_compare_image(const satf_image *img,
                                                  const char *name) {
  compare_image c = {name,
                     satf_image_width(img),
                     satf_image_height(img),
                     fixture_plane(img, "R"),
                     fixture_plane(img, "G"),
                     fixture_plane(img, "B"),
                     fixture_plane(img, "A")};
  return c;
}
#endif

#endif
