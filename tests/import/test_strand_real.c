/* test_strand_real.c - strand files as real tools write them: OBJ
 * polylines (Blender's loose edges, Houdini's whole polylines, relative
 * indices, vertex colours kept, a head's faces beside the hair), PLY with an
 * `nsegs` strand element or only edges, unrecognised bytes, strands of
 * zero length dropped and counted, and Z-up hair turned upright by --up z
 * and placed by --transform; fuzz replays of a valid OBJ. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "import_internal.h"
#include "satf/import.h"
#include "test_util.h"

int fuzz_obj_one(const uint8_t *data, size_t size);

/* Two strands, (0,0,0)-(0,0,1)-(0,0,2) and (1,0,0)-(1,0,1)-(1,0,2)-(1,0,3),
 * in the ways exporters write them. */
static const char OBJ_EDGES[] = "# Blender 3.4.1\no Hair\n"
                                "v 0 0 0\nv 0 0 1\nv 0 0 2\n"
                                "v 1 0 0\nv 1 0 1\nv 1 0 2\nv 1 0 3\n"
                                "l 1 2\nl 2 3\nl 4 5\nl 5 6\nl 6 7\n";
static const char OBJ_POLY[] =
    "mtllib hair.mtl\ng head\nv 9 9 9\nv 9 8 9\nv 8 9 9\nf 1 2 3\n"
    "g hair\nv 0 0 0 0.5 0.25 0.1\nv 0 0 1 0.5 0.25 0.1\nv 0 0 2 0.5 0.25 "
    "0.1\nl 4/1 5/2 6/3\n"
    "v 1 0 0 1\nv 1 0 1 1\nv 1 0 2 1\nv 1 0 3 1\nl -4 -3 -2 -1\n";

static void expect_two(const satf_strand_set *s) {
  assert_int_equal(satf_strand_set_count(s), 2);
  for (int i = 0; i < 2; i++) {
    int n;
    const float *p = satf_strand_set_strand(s, i, &n);
    assert_int_equal(n, 3 + i);
    for (int j = 0; j < n; j++) {
      assert_true(p[3 * j] == (float)i);
      assert_true(p[3 * j + 1] == 0.0f);
      assert_true(p[3 * j + 2] == (float)j);
    }
  }
}

static void obj_fails(const char *text, const char *message) {
  satf_strand_set *s = (satf_strand_set *)1;
  satf_error err;
  assert_int_not_equal(satf_obj_parse(text, strlen(text), "m.obj", &s, &err),
                       SATF_OK);
  assert_null(s);
  assert_string_equal(err.message, message);
}

static void obj_reads(void **state) {
  (void)state;
  satf_strand_set *s;
  satf_error err;
  assert_int_equal(
      satf_obj_parse(OBJ_EDGES, strlen(OBJ_EDGES), "e.obj", &s, &err), SATF_OK);
  expect_two(s);
  satf_strand_set_destroy(s);
  assert_int_equal(
      satf_obj_parse(OBJ_POLY, strlen(OBJ_POLY), "p.obj", &s, &err), SATF_OK);
  expect_two(s);
  satf_strand_set_destroy(s);
  assert_int_equal(satf_strands_detect(OBJ_EDGES, strlen(OBJ_EDGES)),
                   SATF_STRANDS_OBJ);
  assert_int_equal(satf_strands_detect(OBJ_POLY, strlen(OBJ_POLY)),
                   SATF_STRANDS_OBJ);
  assert_int_equal(satf_strands_format_of_name("a/b.obj"), SATF_STRANDS_OBJ);
  obj_fails("v 0 0 0\nv 1 1 1\nf 1 2 1\n",
            "m.obj: no polylines (`l` lines), only faces: nothing says which "
            "vertices form a strand (export the hair as curves or edges)");
  obj_fails("v 0 0 0\nv 1 1 1\nl 1 3\n",
            "m.obj: line 3: a polyline vertex is not an index of the 2 "
            "vertices above it");
  obj_fails("v 0 0 0\nv 1 1 1\nl 1 0\n",
            "m.obj: line 3: a polyline vertex is not an index of the 2 "
            "vertices above it");
  obj_fails("v 0 0\nv 1 1 1\nl 1 2\n",
            "m.obj: line 1: a vertex is `v x y z` with an optional weight or "
            "r g b colour");
  obj_fails("v 0 0 nan\nv 1 1 1\nl 1 2\n",
            "m.obj: line 1: vertex value nan is not a finite float");
  obj_fails("v 0 0 0\nv 1 1 1\nv 2 2 2\nl 1 2\nl 1 3\nl 1 2\n",
            "m.obj: vertex 0 has more than two edges: strands cannot branch");
  obj_fails("v 0 0 0\nl 1\nl 1 1\n",
            "m.obj: line 2: a polyline needs two vertices or more");
}

/* Per-vertex colours (`v x y z r g b`, and after a weight `v x y z w r g
 * b`) kept on the strands' points in chain order (the second strand's
 * vertices written tip first), through the importer's reading and
 * transform (--up z), concatenation and a .hair file written and read
 * back; a file with some vertices uncoloured keeps none, and OBJ gives no
 * width (its fourth number is the rational weight). */
static void obj_colours(void **state) {
  (void)state;
  const char *text = "v 0 0 0 0.1 0.2 0.3\nv 0 0 1 1 0.4 0.5 0.6\n"
                     "v 0 0 2 0.7 0.8 0.9\nv 1 0 2 0.3 0.3 0.3\n"
                     "v 1 0 1 0.2 0.2 0.2\nv 1 0 0 0.15 0.25 0.35\n"
                     "l 1 2 3\nl 6 5 4\n";
  char path[512];
  test_write_file(test_path(path, sizeof path, "real-colour.obj"), text,
                  strlen(text));
  satf_import_options o = satf_import_options_default();
  o.up_z = 1;
  satf_strand_set *s = NULL, *both = NULL, *back = NULL;
  satf_error err;
  assert_int_equal(satf_import_read_strands(path, &o, &s, &err), SATF_OK);
  assert_int_equal(satf_strand_set_count(s), 2);
  assert_null(satf_strand_set_thickness(s, 0));
  /* strand 1 runs from vertex 4 (its lower-numbered end) */
  const float want[2][9] = {
      {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.8f, 0.9f},
      {0.3f, 0.3f, 0.3f, 0.2f, 0.2f, 0.2f, 0.15f, 0.25f, 0.35f}};
  assert_int_equal(satf_strand_set_concat(s, s, &both, &err), SATF_OK);
  test_path(path, sizeof path, "real-colour.hair");
  assert_int_equal(satf_hair_write(path, both, &err), SATF_OK);
  assert_int_equal(satf_hair_read(path, &back, &err), SATF_OK);
  const satf_strand_set *sets[3] = {s, both, back};
  for (int k = 0; k < 3; k++)
    for (int i = 0; i < satf_strand_set_count(sets[k]); i++) {
      const float *c = satf_strand_set_colour(sets[k], i);
      assert_non_null(c);
      for (int j = 0; j < 9; j++)
        if (fabsf(c[j] - want[i % 2][j]) > 1e-7f)
          fail_msg("set %d strand %d colour %d: %g, not %g", k, i, j,
                   (double)c[j], (double)want[i % 2][j]);
    }
  /* --up z turned the points, not the colours: strand 0's tip at y = 2 */
  int n;
  const float *p = satf_strand_set_strand(s, 0, &n);
  assert_true(fabsf(p[3 * (n - 1) + 1] - 2.0f) < 1e-6f);
  satf_strand_set_destroy(s);
  satf_strand_set_destroy(both);
  satf_strand_set_destroy(back);
  remove(path);
  assert_int_equal(
      satf_obj_parse(OBJ_POLY, strlen(OBJ_POLY), "p.obj", &s, &err), SATF_OK);
  assert_null(satf_strand_set_colour(s, 0));
  satf_strand_set_destroy(s);
}

/* The import of `size` bytes written as file `name` fails with `status`
 * and a message holding `message` (the file's path first). */
static void expect_refused(const char *name, const unsigned char *bytes,
                           size_t size, satf_status status,
                           const char *message) {
  char path[512], want[256];
  satf_import_options o = satf_import_options_default();
  satf_strand_set *s = NULL;
  satf_error err;
  test_write_file(test_path(path, sizeof path, name), bytes, size);
  assert_int_equal(satf_import_read_strands(path, &o, &s, &err), status);
  assert_null(s);
  snprintf(want, sizeof want, "%s: %s", name, message);
  if (!strstr(err.message, want))
    fail_msg("expected \"%s\" in \"%s\"", want, err.message);
}

/* Unrecognised bytes are called so, never a TressFX file of some version;
 * a .obj read by the importer. */
static void unknown_format(void **state) {
  (void)state;
  static const char *const unknown =
      "unrecognised format; satf reads .hair, .tfx 3.x/4.x, .ply, .obj, .data";
  unsigned char junk[400];
  for (size_t k = 0; k < sizeof junk; k++)
    junk[k] = (unsigned char)(k * 37 + 11);
  junk[3] = 0x74; /* a first float of 7.6e31 */
  expect_refused("real-junk.bin", junk, sizeof junk, SATF_ERR_FORMAT, unknown);
  /* the same bytes named .tfx: no TressFX version at their start, so not
   * "TressFX version 7.6e31"; a TressFX 5.0 header is named by its version */
  expect_refused("real-junk.tfx", junk, sizeof junk, SATF_ERR_FORMAT, unknown);
  memset(junk, 0, sizeof junk);
  junk[2] = 0xa0;
  junk[3] = 0x40; /* 5.0f */
  expect_refused("real-v5.tfx", junk, sizeof junk, SATF_ERR_VERSION,
                 "TressFX version 5 is not supported (3.x or 4.x expected)");
  char path[512];
  satf_import_options o = satf_import_options_default();
  satf_strand_set *s = NULL;
  satf_error err;
  test_write_file(test_path(path, sizeof path, "real-hair.obj"), OBJ_EDGES,
                  strlen(OBJ_EDGES));
  assert_int_equal(satf_import_read_strands(path, &o, &s, &err), SATF_OK);
  expect_two(s);
  satf_strand_set_destroy(s);
}

/* A PLY whose strand element counts segments in `nsegs`, with an edge
 * element beside it; and one with a count-less strand element and edges. */
static void ply_nsegs(void **state) {
  (void)state;
  const char *nsegs =
      "ply\nformat ascii 1.0\nelement vertex 7\nproperty float x\nproperty "
      "float y\nproperty float z\nelement strand 2\nproperty int nsegs\n"
      "element edge 5\nproperty int vertex1\nproperty int vertex2\n"
      "end_header\n0 0 0\n0 0 1\n0 0 2\n1 0 0\n1 0 1\n1 0 2\n1 0 3\n2\n3\n"
      "0 1\n1 2\n3 4\n4 5\n5 6\n";
  satf_strand_set *s;
  satf_error err;
  assert_int_equal(satf_ply_parse(nsegs, strlen(nsegs), "n.ply", &s, &err),
                   SATF_OK);
  expect_two(s);
  satf_strand_set_destroy(s);
  const char *edges =
      "ply\nformat ascii 1.0\nelement vertex 7\nproperty float x\nproperty "
      "float y\nproperty float z\nelement strand 2\nproperty float length\n"
      "element edge 5\nproperty int vertex1\nproperty int vertex2\n"
      "end_header\n0 0 0\n0 0 1\n0 0 2\n1 0 0\n1 0 1\n1 0 2\n1 0 3\n2\n3\n"
      "0 1\n1 2\n3 4\n4 5\n5 6\n";
  assert_int_equal(satf_ply_parse(edges, strlen(edges), "e.ply", &s, &err),
                   SATF_OK);
  expect_two(s);
  satf_strand_set_destroy(s);
}

/* 16 Z-up strands rising from a 4 x 4 grid, 8 points each, strand 3 with
 * every point at its root, strand 5 with its point 2 repeated. */
static void write_zup(const char *path) {
  char *t = malloc(65536);
  size_t len = 0;
  int v = 0;
  for (int i = 0; i < 16; i++) {
    int first = v + 1;
    for (int j = 0; j < 8; j++, v++) {
      double k = i == 3 ? 0.0 : j; /* strand 3: every point the root */
      for (int twice = 0; twice < 1 + (i == 5 && j == 2); twice++, v++)
        len += (size_t)sprintf(t + len, "v %g %g %g\n", 0.2 * (i % 4),
                               0.2 * (i / 4) + 0.01 * k * k, 0.25 * k);
      v--;
    }
    len += (size_t)sprintf(t + len, "l");
    for (int k = first; k <= v; k++)
      len += (size_t)sprintf(t + len, " %d", k);
    len += (size_t)sprintf(t + len, "\n");
  }
  test_write_file(path, t, len);
  free(t);
}

static satf_status import_zup(const char *in, satf_import_options *o,
                              satf_import_result *r, satf_scene **scene,
                              satf_error *err) {
  static char out[1024];
  test_path(out, sizeof out, "real-zup.json");
  o->inputs[0] = in;
  o->n_inputs = 1;
  o->output = out;
  o->quiet = 1;
  o->clusters = 2;
  satf_status st = satf_import_run(o, r, err);
  if (st == SATF_OK)
    assert_int_equal(satf_scene_load(out, scene, err), SATF_OK);
  return st;
}

static void zero_length_and_up(void **state) {
  (void)state;
  char in[512];
  write_zup(test_path(in, sizeof in, "real-zup.obj"));
  satf_import_options o = satf_import_options_default();
  satf_import_result r;
  satf_scene *scene = NULL;
  satf_error err;
  /* as written: the strands run along z, the camera's up is y */
  assert_int_equal(import_zup(in, &o, &r, &scene, &err), SATF_OK);
  assert_int_equal(r.n_strands, 15);
  assert_int_equal(r.dropped_strands, 1);
  assert_int_equal(r.merged_points, 1);
  assert_int_equal(r.n_points, 15 * 8);
  float target_y = scene->camera.target[1], target_z = scene->camera.target[2];
  assert_true(fabsf(target_z - 0.875f) < 0.1f);
  satf_scene_destroy(scene);
  /* --up z: upright, the hair's height along y, centred on the camera */
  o = satf_import_options_default();
  o.up_z = 1;
  assert_int_equal(import_zup(in, &o, &r, &scene, &err), SATF_OK);
  print_message(
      "target %g %g %g (before: y %g z %g)\n", (double)scene->camera.target[0],
      (double)scene->camera.target[1], (double)scene->camera.target[2],
      (double)target_y, (double)target_z);
  assert_true(fabsf(scene->camera.target[1] - 0.875f) < 0.1f);
  assert_true(fabsf(scene->camera.target[2] + target_y) < 0.1f);
  assert_true(scene->camera.position[2] > scene->camera.target[2]);
  assert_true(scene->camera.up[1] == 1.0f);
  satf_scene_destroy(scene);
  /* --transform translate=0,10,0 after --up z */
  o = satf_import_options_default();
  o.up_z = 1;
  o.hair_translate[1] = 10.0;
  assert_int_equal(import_zup(in, &o, &r, &scene, &err), SATF_OK);
  assert_true(fabsf(scene->camera.target[1] - 10.875f) < 0.1f);
  satf_scene_destroy(scene);
  /* a file of nothing but zero-length strands is refused, named */
  const char *dead = "v 1 1 1\nv 1 1 1\nl 1 2\n";
  test_write_file(test_path(in, sizeof in, "real-dead.obj"), dead,
                  strlen(dead));
  o = satf_import_options_default();
  assert_int_not_equal(import_zup(in, &o, &r, &scene, &err), SATF_OK);
  print_message("dead: %s\n", err.message);
  assert_non_null(strstr(err.message, "real-dead.obj: "));
}

static void fuzz_replays(void **state) {
  (void)state;
  test_replay_mutations(fuzz_obj_one, (const unsigned char *)OBJ_POLY,
                        strlen(OBJ_POLY));
  test_replay_mutations(fuzz_obj_one, (const unsigned char *)OBJ_EDGES,
                        strlen(OBJ_EDGES));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(obj_reads),          cmocka_unit_test(obj_colours),
      cmocka_unit_test(unknown_format),     cmocka_unit_test(ply_nsegs),
      cmocka_unit_test(zero_length_and_up), cmocka_unit_test(fuzz_replays)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
