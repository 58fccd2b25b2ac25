/* test_tracks.c - density from a cluster's own strands (scene density type
 * "tracks", satf/density.h): values at and between slices, strands that
 * start late and end early (the falling density at a cluster's end), the
 * scene round trip, and malformed tracks. */
#define _POSIX_C_SOURCE 200809L
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

#include "satf/density.h"
#include "satf/scene.h"

/* Two strands over 5 slices (t = 0, 0.25, 0.5, 0.75, 1): strand 0 from the
 * root to the tip, moving in x from -0.5 to 0.5; strand 1 from slice 1 to
 * slice 2 only (a short strand), fixed at (0, 0.6). */
static const char *scene_json =
    "{\"macro_clusters\": [{\"prototype\": {"
    "  \"trajectory\": [[0, 0, 0], [0, 4, 0]], \"a\": 1,"
    "  \"density\": {\"type\": \"tracks\", \"slices\": 5,"
    "    \"strand_width\": 0.1, \"scale\": 2,"
    "    \"tracks\": [[0, -0.5, 0, -0.25, 0, 0, 0, 0.25, 0, 0.5, 0],"
    "                [1, 0, 0.6, 0, 0.6]]}}}]}";

static satf_scene *parse(const char *json, satf_error *err) {
  satf_scene *s = NULL;
  satf_scene_parse(json, strlen(json), "t.json", &s, err);
  return s;
}

static void test_values(void **state) {
  (void)state;
  satf_error err;
  satf_scene *scene = parse(scene_json, &err);
  assert_non_null(scene);
  const satf_scene_density *d = &scene->macro_clusters[0].prototype.density;
  assert_int_equal(d->type, SATF_SCENE_DENSITY_TRACKS);
  assert_int_equal(d->n_tracks, 2);
  satf_strands *s = NULL;
  assert_int_equal(satf_strands_create(d, &s, &err), SATF_OK);
  assert_int_equal(satf_strands_count(s), 2);
  /* on a strand alone: the Gaussian's peak 1/2 times scale 2 */
  assert_true(fabsf(satf_strands_density(s, 0.0f, -0.5f, 0.0f) - 1.0f) < 1e-5);
  /* between slices the strand moves linearly: at t = 0.375 it is at
   * x = -0.5 + 1.5 * 0.25 = -0.125 */
  float p[2];
  satf_strands_position(s, 0, 0.375f, p);
  assert_true(fabsf(p[0] + 0.125f) < 1e-5 && fabsf(p[1]) < 1e-6);
  assert_true(fabsf(satf_strands_density(s, 0.375f, -0.125f, 0.0f) - 1.0f) <
              1e-5);
  /* one strand width (2 sigma) away: exp(-2) of the peak */
  float off = satf_strands_density(s, 0.375f, -0.125f + 0.1f, 0.0f);
  assert_true(fabsf(off - expf(-2.0f)) < 1e-4);
  /* the short strand: full between its slices, fading over the interval
   * after its tip (t in [0.5, 0.75]) and before its root ([0, 0.25]) */
  assert_true(fabsf(satf_strands_density(s, 0.375f, 0.0f, 0.6f) - 1.0f) < 1e-4);
  assert_true(fabsf(satf_strands_density(s, 0.5625f, 0.0f, 0.6f) - 0.75f) <
              1e-4);
  assert_true(fabsf(satf_strands_density(s, 0.125f, 0.0f, 0.6f) - 0.5f) < 1e-4);
  assert_true(satf_strands_density(s, 0.9f, 0.0f, 0.6f) < 1e-6);
  /* far from both strands: nothing */
  assert_true(satf_strands_density(s, 0.5f, 0.0f, -0.8f) < 1e-6);
  satf_strands_destroy(s);
  satf_scene_destroy(scene);
}

/* The bucket grid finds every strand: density by brute force over many
 * random strands agrees everywhere. */
static void test_against_brute_force(void **state) {
  (void)state;
  enum { N = 300, SLICES = 9 };
  size_t cap = (size_t)N * (SLICES * 2 * 24 + 8) + 512;
  char *json = malloc(cap);
  assert_non_null(json);
  size_t at = (size_t)snprintf(
      json, cap,
      "{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0, 0, 0], "
      "[0, 4, 0]], \"a\": 1, \"density\": {\"type\": \"tracks\", "
      "\"slices\": %d, \"strand_width\": 0.08, \"tracks\": [",
      SLICES);
  unsigned seed = 12345;
  float xy[N][SLICES][2];
  int first[N], count[N];
  for (int k = 0; k < N; k++) {
    seed = seed * 1103515245u + 12345u;
    first[k] = (int)(seed >> 16) % 3;
    seed = seed * 1103515245u + 12345u;
    count[k] = 2 + (int)((seed >> 16) % (unsigned)(SLICES - first[k] - 1));
    at +=
        (size_t)snprintf(json + at, cap - at, "%s[%d", k ? ", " : "", first[k]);
    for (int i = 0; i < count[k]; i++)
      for (int c = 0; c < 2; c++) {
        seed = seed * 1103515245u + 12345u;
        xy[k][i][c] = (float)((seed >> 8) % 20001u) / 10000.0f - 1.0f;
        at += (size_t)snprintf(json + at, cap - at, ", %.4f", xy[k][i][c]);
        xy[k][i][c] = strtof(strrchr(json, ' ') + 1, NULL);
      }
    at += (size_t)snprintf(json + at, cap - at, "]");
  }
  snprintf(json + at, cap - at, "]}}}]}");
  satf_error err;
  satf_scene *scene = parse(json, &err);
  if (!scene)
    fail_msg("%s", err.message);
  satf_strands *s = NULL;
  assert_int_equal(satf_strands_create(
                       &scene->macro_clusters[0].prototype.density, &s, &err),
                   SATF_OK);
  float sigma = 0.04f, worst = 0.0f;
  for (int q = 0; q < 2000; q++) {
    seed = seed * 1103515245u + 12345u;
    float t = (float)((seed >> 8) % 10001u) / 10000.0f;
    seed = seed * 1103515245u + 12345u;
    float x = (float)((seed >> 8) % 20001u) / 10000.0f - 1.0f;
    seed = seed * 1103515245u + 12345u;
    float y = (float)((seed >> 8) % 20001u) / 10000.0f - 1.0f;
    float g = t * (SLICES - 1);
    int i = (int)floorf(g);
    if (i > SLICES - 2)
      i = SLICES - 2;
    float f = g - (float)i, want = 0.0f;
    for (int k = 0; k < N; k++) {
      int ia = i - first[k], ib = i + 1 - first[k];
      int ha = ia >= 0 && ia < count[k], hb = ib >= 0 && ib < count[k];
      float p[2], w = 1.0f;
      if (ha && hb) {
        p[0] = xy[k][ia][0] + f * (xy[k][ib][0] - xy[k][ia][0]);
        p[1] = xy[k][ia][1] + f * (xy[k][ib][1] - xy[k][ia][1]);
      } else if (ha) {
        p[0] = xy[k][ia][0], p[1] = xy[k][ia][1], w = 1.0f - f;
      } else if (hb) {
        p[0] = xy[k][ib][0], p[1] = xy[k][ib][1], w = f;
      } else
        continue;
      float d2 = (x - p[0]) * (x - p[0]) + (y - p[1]) * (y - p[1]);
      if (d2 < 16.0f * sigma * sigma)
        want += w * 0.5f * expf(-d2 / (2.0f * sigma * sigma));
    }
    float got = satf_strands_density(s, t, x, y);
    float e = fabsf(got - want);
    worst = e > worst ? e : worst;
  }
  printf("tracks density against brute force: worst |error| %g\n",
         (double)worst);
  assert_true(worst < 1e-4f);
  satf_strands_destroy(s);
  satf_scene_destroy(scene);
  free(json);
}

/* The scene in json written and read back is the same scene, a snapshot
 * copies its prototype, and a value moved in the read-back copy's float
 * array at changed_offset in the density makes it another scene. */
static void assert_round_trip(const char *json_in, size_t changed_offset) {
  satf_error err;
  satf_scene *a = parse(json_in, &err);
  if (!a)
    fail_msg("%s", err.message);
  char *json = NULL;
  assert_int_equal(satf_scene_to_json(a, NULL, &json, &err), SATF_OK);
  satf_scene *b = parse(json, &err);
  if (!b)
    fail_msg("%s\n%s", err.message, json);
  assert_true(satf_scene_equal(a, b));
  float **field = (float **)((char *)&b->macro_clusters[0].prototype.density +
                             changed_offset);
  (*field)[3] += 0.01f;
  assert_false(satf_scene_equal(a, b));
  satf_scene *snap = NULL;
  assert_int_equal(satf_scene_at_frame(a, 1.0, &snap, &err), SATF_OK);
  assert_true(satf_scene_prototype_equal(&a->macro_clusters[0].prototype,
                                         &snap->macro_clusters[0].prototype));
  free(json);
  satf_scene_destroy(snap);
  satf_scene_destroy(a);
  satf_scene_destroy(b);
}

static void test_round_trip(void **state) {
  (void)state;
  /* a changed point is a different scene */
  assert_round_trip(scene_json, offsetof(satf_scene_density, track_xy));
}

/* A short strand's true ends, where they lie between slices ("ends"):
 * written back as read, part of the scene's identity, copied by a
 * snapshot. */
static const char *ends_json =
    "{\"macro_clusters\": [{\"prototype\": {"
    "  \"trajectory\": [[0, 0, 0], [0, 4, 0]], \"a\": 1,"
    "  \"density\": {\"type\": \"tracks\", \"slices\": 5,"
    "    \"tracks\": [[0, -0.5, 0, -0.25, 0, 0, 0, 0.25, 0, 0.5, 0],"
    "                [1, 0, 0.6, 0, 0.6]],"
    "    \"ends\": [[0, -0.5, 0, 1, 0.5, 0], [0.2, 0, 0.6, 0.6, 0.1, 0.6]]}"
    "}}]}";

static void test_ends_round_trip(void **state) {
  (void)state;
  satf_error err;
  satf_scene *a = parse(ends_json, &err);
  if (!a)
    fail_msg("%s", err.message);
  const satf_scene_density *d = &a->macro_clusters[0].prototype.density;
  assert_non_null(d->track_ends);
  assert_true(fabsf(d->track_ends[6] - 0.2f) < 1e-7f);
  assert_true(fabsf(d->track_ends[10] - 0.1f) < 1e-7f);
  /* the same tracks without ends are another scene */
  satf_scene *c = parse(scene_json, &err);
  assert_non_null(c);
  assert_false(satf_scene_equal(a, c));
  satf_scene_destroy(a);
  satf_scene_destroy(c);
  assert_round_trip(ends_json, offsetof(satf_scene_density, track_ends));
}

/* Which clusters the renderer draws as their strands: few strands, or a
 * tuft of short ones (each crossing at most half of the slices on
 * average); never with max 0. */
static void test_as_strands(void **state) {
  (void)state;
  int counts[12];
  for (int k = 0; k < 12; k++)
    counts[k] = 5;
  assert_true(satf_scene_tracks_as_strands(10, 8, counts, 8));
  assert_false(satf_scene_tracks_as_strands(10, 8, counts, 0));
  /* above max, but a tuft */
  assert_true(satf_scene_tracks_as_strands(10, 8, counts, 7));
  /* 12 strands over half the slices each: a tuft */
  assert_true(satf_scene_tracks_as_strands(10, 12, counts, 8));
  counts[0] = 6; /* one slice more: longer than half on average */
  assert_false(satf_scene_tracks_as_strands(10, 12, counts, 8));
  for (int k = 0; k < 12; k++)
    counts[k] = 9;
  assert_false(satf_scene_tracks_as_strands(10, 12, counts, 8));
  assert_true(satf_scene_tracks_as_strands(10, 12, counts, 12));
  assert_false(satf_scene_tracks_as_strands(10, 0, counts, 8));
  assert_false(satf_scene_tracks_as_strands(1, 12, counts, 8));
}

static void test_malformed(void **state) {
  (void)state;
  static const struct {
    const char *density, *message;
  } cases[] = {
      {"\"slices\": 5, \"tracks\": [[0, 1, 2, 3]]",
       "tracks[0]: expected [first slice, x, y, x, y, ...]"},
      {"\"slices\": 3, \"tracks\": [[2, 0, 0, 0, 0]]",
       "tracks[0]: slices 2 to 3: the density has 3 slices"},
      {"\"slices\": 3, \"tracks\": [[0, 0, 9]]", "tracks[0]"},
      {"\"slices\": 3, \"tracks\": [[-1, 0, 0]]", "tracks[0]"},
      {"\"slices\": 3, \"tracks\": [[0.5, 0, 0]]", "tracks[0]"},
      {"\"tracks\": [[0, 0, 0]]", "slices"},
      {"\"slices\": 1, \"tracks\": [[0, 0, 0]]", "slices"},
      {"\"slices\": 3", "tracks"},
      {"\"slices\": 3, \"tracks\": [], \"x\": 1", "tracks"},
      {"\"slices\": 3, \"tracks\": [\"a\"]", "tracks[0]"},
      {"\"slices\": 3, \"tracks\": [[0, 0, 0]], \"ends\": []",
       "ends: has 0 entries, expected 1 to 1"},
      {"\"slices\": 3, \"tracks\": [[0, 0, 0]], \"ends\": [[0, 0, 0]]",
       "ends[0]"},
      {"\"slices\": 3, \"tracks\": [[0, 0, 0]], "
       "\"ends\": [[0.5, 0, 0, 0.2, 0, 0]]",
       "ends[0]: expected [t, x, y, t, x, y] with 0 <= t <= t <= 1"},
      {"\"slices\": 3, \"tracks\": [[0, 0, 0]], "
       "\"ends\": [[0, 0, 0, 1.5, 0, 0]]",
       "ends[0]: expected [t, x, y, t, x, y]"},
      {"\"slices\": 3, \"tracks\": [[0, 0, 0]], "
       "\"ends\": [[0, 0, 0, 1, 9, 0]]",
       "ends[0]"},
      {"\"slices\": 3, \"tracks\": [[0, 0, 0]], \"ends\": 4", "ends"},
  };
  for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
    char json[1024];
    snprintf(json, sizeof json,
             "{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0, 0, "
             "0], [0, 4, 0]], \"a\": 1, \"density\": {\"type\": \"tracks\", "
             "%s}}}]}",
             cases[c].density);
    satf_error err;
    satf_scene *s = parse(json, &err);
    if (s)
      fail_msg("accepted: %s", cases[c].density);
    printf("%s\n", err.message);
    assert_non_null(strstr(err.message, "density"));
    assert_non_null(strstr(err.message, cases[c].message));
  }
  /* a procedural key in a tracks density is a warning naming it */
  const char *json =
      "{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0, 0, 0], "
      "[0, 4, 0]], \"a\": 1, \"density\": {\"type\": \"tracks\", "
      "\"slices\": 3, \"strands\": 4, \"tracks\": [[0, 0, 0]]}}}]}";
  satf_error err;
  satf_scene *s = parse(json, &err);
  assert_non_null(s);
  assert_int_equal(satf_scene_warning_count(s), 1);
  assert_non_null(strstr(satf_scene_warning(s, 0), "strands"));
  satf_scene_destroy(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_values),
      cmocka_unit_test(test_against_brute_force),
      cmocka_unit_test(test_round_trip),
      cmocka_unit_test(test_ends_round_trip),
      cmocka_unit_test(test_as_strands),
      cmocka_unit_test(test_malformed),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
