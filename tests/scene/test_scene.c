/* test_scene.c - scene file parsing: the samples' Table-1 counts, defaults,
 * one message per malformed case, warnings, path resolution, instance
 * transforms, and a replay of generated malformed inputs through the fuzz
 * target's checks. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "satf/common.h"
#include "satf/scene.h"
#include "scene_cases.h"

int satf_fuzz_scene_one(const uint8_t *data, size_t size);

#define MINIMAL_CLUSTER                                                        \
  "{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]], \"a\": 0.5}}"
#define MINIMAL "{\"macro_clusters\": [" MINIMAL_CLUSTER "]}"

/* ---- samples: SATF Table 1 columns 6(a)-6(d), 7(a)-7(d), 8 (animated; its
 * keyframes are test_anim's) ---- */

typedef struct sample_case {
  const char *file;
  uint64_t clusters, layers;
  double hsv, strands; /* the table's figures, in units */
  satf_scene_layout layout;
} sample_case;

static const sample_case samples[] = {
    {"cluster_6a.json", 1, 15, 16000, 3000, SATF_SCENE_LAYOUT_UNIFORM},
    {"cluster_6b.json", 1, 15, 16000, 3000, SATF_SCENE_LAYOUT_GRADIENT},
    {"cluster_6c.json", 1, 10, 11000, 2000, SATF_SCENE_LAYOUT_HOLES},
    {"cluster_6d.json", 1, 15, 16000, 3000, SATF_SCENE_LAYOUT_CLUMPED},
    {"hair_7a.json", 17, 51, 54000, 14000, SATF_SCENE_LAYOUT_COUNT},
    {"hair_7b.json", 12, 60, 61000, 20000, SATF_SCENE_LAYOUT_COUNT},
    {"hair_7c.json", 4, 60, 127000, 20000, SATF_SCENE_LAYOUT_COUNT},
    {"hair_7d.json", 6, 60, 63000, 9000, SATF_SCENE_LAYOUT_COUNT},
    {"anim_8.json", 40, 80, 42000, 21000, SATF_SCENE_LAYOUT_COUNT},
};
#define N_SAMPLES (sizeof samples / sizeof samples[0])

static void test_samples_match_table1(void **state) {
  (void)state;
  for (size_t i = 0; i < N_SAMPLES; i++) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", SATF_SAMPLES_DIR, samples[i].file);
    satf_scene *scene = NULL;
    satf_error err;
    satf_status s = satf_scene_load(path, &scene, &err);
    if (s != SATF_OK)
      fprintf(stderr, "%s\n", err.message);
    assert_int_equal(s, SATF_OK);
    for (int w = 0; w < satf_scene_warning_count(scene); w++)
      fprintf(stderr, "warning: %s\n", satf_scene_warning(scene, w));
    assert_int_equal(satf_scene_warning_count(scene), 0);
    assert_int_equal(satf_scene_cluster_count(scene), samples[i].clusters);
    assert_int_equal(satf_scene_layer_count(scene), samples[i].layers);
    double hsv = (double)satf_scene_hsv_count(scene);
    assert_true(fabs(hsv - samples[i].hsv) <= 0.05 * samples[i].hsv);
    double strands = (double)satf_scene_strand_count(scene);
    assert_true(fabs(strands - samples[i].strands) <=
                0.05 * samples[i].strands);
    if (samples[i].layout != SATF_SCENE_LAYOUT_COUNT)
      assert_int_equal(scene->macro_clusters[0].prototype.density.layout,
                       samples[i].layout);
    /* "../out/..." resolved against samples/. */
    char db[600];
    snprintf(db, sizeof db, "%s/../out/satf-default.hrirdb.exr",
             SATF_SAMPLES_DIR);
    assert_string_equal(scene->database, db);
    assert_int_equal(scene->camera.automatic, 0);
    assert_true(scene->n_lights >= 1);
    satf_scene_destroy(scene);
  }
}

static void test_hairstyle_hierarchy(void **state) {
  (void)state;
  satf_scene *scene = NULL;
  assert_int_equal(
      satf_scene_load(SATF_SAMPLES_DIR "/hair_7a.json", &scene, NULL), SATF_OK);
  /* A real macro-cluster level: few prototypes, several instances each. */
  assert_int_equal(scene->n_macro_clusters, 3);
  float roots[17][3];
  int n = 0;
  for (int i = 0; i < scene->n_macro_clusters; i++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[i];
    assert_true(mc->n_instances >= 3);
    assert_int_equal(mc->prototype.shell.layers, 3);
    for (int j = 0; j < mc->n_instances; j++) {
      assert_true(n < 17);
      satf_scene_instance_apply(&mc->instances[j], mc->prototype.trajectory,
                                roots[n]);
      /* Rotations about the head's centre keep every root on the scalp
       * (radius 10) offset by about the cluster's half minor axis. */
      double d = sqrt(roots[n][0] * roots[n][0] + roots[n][1] * roots[n][1] +
                      roots[n][2] * roots[n][2]);
      assert_true(d > 10.0 && d < 11.5);
      n++;
    }
  }
  assert_int_equal(n, 17);
  for (int a = 0; a < n; a++)
    for (int b = a + 1; b < n; b++) {
      double dx = roots[a][0] - roots[b][0], dy = roots[a][1] - roots[b][1],
             dz = roots[a][2] - roots[b][2];
      assert_true(sqrt(dx * dx + dy * dy + dz * dz) > 1.0);
    }
  satf_scene_destroy(scene);
}

/* ---- defaults ---- */

static void test_defaults(void **state) {
  (void)state;
  satf_scene *scene = parse_ok(MINIMAL, "min.json");
  assert_int_equal(satf_scene_warning_count(scene), 0);
  assert_int_equal(scene->n_macro_clusters, 1);
  const satf_scene_macro_cluster *mc = &scene->macro_clusters[0];
  assert_null(mc->name);
  assert_int_equal(mc->n_instances, 1);
  for (int k = 0; k < 16; k++)
    assert_true(mc->instances[0].m[k] == ((k % 5 == 0) ? 1.0f : 0.0f));
  const satf_scene_cluster *c = &mc->prototype;
  assert_int_equal(c->n_points, 2);
  assert_true(c->trajectory[4] == 1.0f);
  assert_int_equal(c->a.count, 1);
  assert_true(c->a.values[0] == 0.5f);
  assert_int_equal(c->b.count, 1); /* b defaults to a */
  assert_true(c->b.values[0] == 0.5f);
  assert_int_equal(c->twist.count, 1);
  assert_true(c->twist.values[0] == 0.0f);
  assert_int_equal(c->shell.layers, 3);
  assert_int_equal(c->shell.st, 32);
  assert_int_equal(c->shell.su, 16);
  assert_true(c->shell.core == 0.5f);
  const satf_scene_density *d = &c->density;
  assert_int_equal(d->type, SATF_SCENE_DENSITY_PROCEDURAL);
  assert_int_equal(d->strands, 1000);
  assert_int_equal(d->seed, 1);
  assert_int_equal(d->layout, SATF_SCENE_LAYOUT_UNIFORM);
  assert_true(d->strand_width == 0.03f && d->scale == 1.0f);
  assert_int_equal(d->clumps, 8);
  assert_int_equal(d->holes, 4);
  assert_null(d->vdb_file);

  const satf_scene_material *m = &scene->material;
  assert_true(m->k_dif == 0.7f && m->k_speI == 0.3f && m->k_speII == 0.4f);
  assert_true(m->exponent_I == 80.0f && m->exponent_II == 24.0f);
  assert_true(m->shift_I == 0.1f && m->shift_II == 0.1f);
  assert_true(m->f_dif[0] == 0.24f && m->f_dif[1] == 0.15f &&
              m->f_dif[2] == 0.09f);
  assert_true(m->f_speI[0] == 1.0f && m->f_speII[0] == 0.55f);
  assert_true(m->k_shadow == 0.6f && m->noise == 0.5f);
  /* The fibre takes Cycles' Principled Hair defaults; the paper's model
   * stays the default shading. */
  assert_int_equal(m->model, SATF_MATERIAL_KK);
  assert_true(m->melanin == 0.6f && m->redness == 0.0f);
  assert_true(m->roughness == 0.3f && m->radial_roughness == 0.3f);
  assert_true(m->cuticle_tilt == 2.0f && m->ior == 1.55f);
  assert_int_equal(m->has_absorption, 0);
  /* Dark brown: red > green > blue, all dark. */
  assert_true(m->f_dif[0] > m->f_dif[1] && m->f_dif[1] > m->f_dif[2] &&
              m->f_dif[0] < 0.35f);

  assert_true(scene->effects.satf && scene->effects.secondary_highlight &&
              scene->effects.self_shadow && scene->effects.cluster_shadows);
  assert_int_equal(scene->image.width, 640);
  assert_int_equal(scene->image.height, 480);
  assert_null(scene->database);
  assert_null(scene->strands_file);
  assert_null(scene->description);
  assert_true(scene->background[0] == 0.1f && scene->background[2] == 0.12f);

  /* One directional key light travelling from (0.4, 0.5, 0.75). */
  assert_int_equal(scene->n_lights, 1);
  const satf_scene_light *l = &scene->lights[0];
  assert_int_equal(l->type, SATF_SCENE_LIGHT_DIRECTIONAL);
  double len = sqrt(0.4 * 0.4 + 0.5 * 0.5 + 0.75 * 0.75);
  assert_near(l->direction[0], -0.4 / len, 1e-6);
  assert_near(l->direction[2], -0.75 / len, 1e-6);
  assert_true(l->intensity == 1.0f && l->color[1] == 1.0f);

  /* Automatic camera: bounds are the segment (0,0,0)-(0,1,0) grown by 0.5,
   * i.e. [-0.5,0.5] x [-0.5,1.5] x [-0.5,0.5]; centre (0, 0.5, 0), bounding
   * radius sqrt(6)/2 = 1.224745; distance 1.1 r / sin(20 deg) = 3.939036. */
  const satf_scene_camera *cam = &scene->camera;
  assert_int_equal(cam->automatic, 1);
  assert_true(cam->fov_y == 40.0f);
  assert_near(cam->target[0], 0.0, 1e-6);
  assert_near(cam->target[1], 0.5, 1e-6);
  assert_near(cam->target[2], 0.0, 1e-6);
  assert_near(cam->position[1], 0.5, 1e-6);
  assert_near(cam->position[2], 3.939036, 1e-4);
  assert_true(cam->up[1] == 1.0f);
  assert_true(cam->near_clip == 0.0f && cam->far_clip == 0.0f);
  satf_scene_destroy(scene);
}

static void test_explicit_values(void **state) {
  (void)state;
  const char *json =
      "{\"macro_clusters\": [{\"name\": \"n\", \"prototype\": {"
      "  \"trajectory\": [[0,0,0],[1,0,0],[2,1,0]],"
      "  \"a\": [1, 2, 3], \"b\": 0.25, \"twist\": [0, 3.14, 1],"
      "  \"shell\": {\"layers\": 7, \"st\": 9, \"su\": 5, \"core\": 0.95},"
      "  \"density\": {\"type\": \"vdb\", \"file\": \"d.vdb\"}}}],"
      " \"material\": {\"shift\": 0.2, \"shift_II\": -0.3, \"k_dif\": 0.5},"
      " \"effects\": {\"satf\": false, \"cluster_shadows\": false},"
      " \"camera\": {\"position\": [0,0,10], \"target\": [1,0,0],"
      "   \"up\": [0,2,0], \"fov_y\": 60, \"near\": 0.5, \"far\": 100},"
      " \"lights\": [{\"type\": \"point\", \"position\": [1,2,3],"
      "   \"color\": [1,0.5,0], \"intensity\": 400},"
      "  {\"direction\": [0,0,-3]}],"
      " \"background\": [0,0,0], \"image\": {\"width\": 320, \"height\": 1}}";
  satf_scene *scene = parse_ok(json, "x.json");
  assert_int_equal(satf_scene_warning_count(scene), 0);
  const satf_scene_cluster *c = &scene->macro_clusters[0].prototype;
  assert_string_equal(scene->macro_clusters[0].name, "n");
  assert_int_equal(c->a.count, 3);
  assert_true(c->a.values[2] == 3.0f);
  assert_true(c->b.count == 1 && c->b.values[0] == 0.25f);
  assert_true(c->twist.count == 3 && c->twist.values[1] == 3.14f);
  /* Shared control polygon: b's constant repeated to a's count. */
  assert_int_equal(satf_scene_cluster_curve_count(c), 3);
  float b3[3];
  satf_scene_curve_expand(&c->b, 3, b3);
  assert_true(b3[0] == 0.25f && b3[1] == 0.25f && b3[2] == 0.25f);
  satf_scene_curve_expand(&c->a, 3, b3);
  assert_true(b3[0] == 1.0f && b3[1] == 2.0f && b3[2] == 3.0f);
  assert_int_equal(satf_scene_cluster_hsv_count(c), 7 * 9 * 5);
  assert_int_equal(c->density.type, SATF_SCENE_DENSITY_VDB);
  assert_string_equal(c->density.vdb_file, "d.vdb"); /* no directory */
  assert_string_equal(c->density.vdb_grid, "density");
  assert_int_equal(satf_scene_strand_count(scene), 0);
  assert_true(scene->material.shift_I == 0.2f);
  assert_true(scene->material.shift_II == -0.3f);
  assert_true(scene->material.k_dif == 0.5f);
  assert_true(!scene->effects.satf && scene->effects.secondary_highlight &&
              scene->effects.self_shadow && !scene->effects.cluster_shadows);
  assert_int_equal(scene->camera.automatic, 0);
  assert_true(scene->camera.up[1] == 1.0f); /* normalized */
  assert_true(scene->camera.fov_y == 60.0f);
  assert_true(scene->camera.near_clip == 0.5f &&
              scene->camera.far_clip == 100.0f);
  assert_int_equal(scene->n_lights, 2);
  assert_int_equal(scene->lights[0].type, SATF_SCENE_LIGHT_POINT);
  assert_true(scene->lights[0].position[2] == 3.0f);
  assert_true(scene->lights[0].intensity == 400.0f);
  assert_true(scene->lights[0].color[1] == 0.5f);
  assert_int_equal(scene->lights[1].type, SATF_SCENE_LIGHT_DIRECTIONAL);
  assert_true(scene->lights[1].direction[2] == -1.0f);
  assert_int_equal(scene->image.width, 320);
  assert_int_equal(scene->image.height, 1);
  satf_scene_destroy(scene);
}

/* ---- malformed input: each case its own message with its key path ---- */

#define CLUSTER_WITH(extra)                                                    \
  "{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]],"  \
  " \"a\": 0.5" extra "}}]}"
#define SCENE_WITH(extra) "{\"macro_clusters\": [" MINIMAL_CLUSTER "]" extra "}"

static const bad_case bad_cases[] = {
    {"{\"macro_clusters\": [}", SATF_ERR_FORMAT,
     "bad.json:1:21: malformed JSON near \"}\""},
    {"{\"macro_clusters\": [", SATF_ERR_FORMAT,
     "bad.json:1:21: malformed JSON: unexpected end of input"},
    {"", SATF_ERR_FORMAT, "bad.json:1:1: malformed JSON: unexpected end of"},
    {MINIMAL " x", SATF_ERR_FORMAT, "malformed JSON near \"x\""},
    {"[1, 2]", SATF_ERR_FORMAT,
     "bad.json: (root): expected an object, got an "
     "array"},
    {"{}", SATF_ERR_FORMAT, "bad.json: macro_clusters: missing required key"},
    {"{\"macro_clusters\": []}", SATF_ERR_ARGUMENT,
     "macro_clusters: has 0 entries, expected 1 to 65536"},
    {"{\"macro_clusters\": {}}", SATF_ERR_FORMAT,
     "macro_clusters: expected an array, got an object"},
    {"{\"macro_clusters\": [7]}", SATF_ERR_FORMAT,
     "macro_clusters[0]: expected an object, got a number"},
    {"{\"macro_clusters\": [{}]}", SATF_ERR_FORMAT,
     "macro_clusters[0].prototype: missing required key"},
    {"{\"macro_clusters\": [{\"prototype\": {\"a\": 1}}]}", SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.trajectory: missing required key"},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0]], "
     "\"a\": 1}}]}",
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.trajectory: has 1 entries, expected 2 to "
     "4096"},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1]], "
     "\"a\": 1}}]}",
     SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.trajectory[1]: expected an array of 3 "
     "numbers, got 2 entries"},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,0,0]],"
     " \"a\": 1}}]}",
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.trajectory: all 2 control points coincide"},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1e400,"
     "0]], \"a\": 1}}]}",
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.trajectory[1][1]: number is too large to "
     "represent (parsed as inf)"},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]]"
     "}}]}",
     SATF_ERR_FORMAT, "macro_clusters[0].prototype.a: missing required key"},
    {CLUSTER_WITH(", \"b\": -0.5"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.b: -0.5 is out of range (0, 1000000]"},
    {CLUSTER_WITH(", \"b\": [0.5, 0]"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.b[1]: 0 is out of range (0, 1000000]"},
    {CLUSTER_WITH(", \"b\": [0.5, -1e400]"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.b[1]: number is too large to represent "
     "(parsed as -inf)"},
    {CLUSTER_WITH(", \"b\": \"thin\""), SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.b: expected a number or an array of "
     "numbers, got a string"},
    {CLUSTER_WITH(", \"b\": []"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.b: has 0 control values, expected 1 to "
     "4096"},
    {CLUSTER_WITH(", \"twist\": [0, true]"), SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.twist[1]: expected a number, got a boolean"},
    {CLUSTER_WITH(", \"b\": [1, 2], \"twist\": [0, 1, 2]"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.twist: has 3 control values but b has 2; "
     "a, b and twist need the same count (or a single number)"},
    {CLUSTER_WITH(", \"shell\": {\"layers\": 0}"), SATF_ERR_ARGUMENT,
     "bad.json: macro_clusters[0].prototype.shell.layers: 0 is out of range "
     "[1, 256]"},
    {CLUSTER_WITH(", \"shell\": {\"layers\": 100000}"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.shell.layers: 100000 is out of range [1, "
     "256]"},
    {CLUSTER_WITH(", \"shell\": {\"layers\": 2.5}"), SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.shell.layers: 2.5 is not an integer"},
    {CLUSTER_WITH(", \"shell\": {\"layers\": \"3\"}"), SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.shell.layers: expected an integer, got a "
     "string"},
    {CLUSTER_WITH(", \"shell\": {\"su\": 2}"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.shell.su: 2 is out of range [3, 4096]"},
    {CLUSTER_WITH(", \"shell\": {\"st\": 5000}"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.shell.st: 5000 is out of range [1, 4096]"},
    {CLUSTER_WITH(", \"shell\": {\"core\": 0.99}"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.shell.core: 0.99 is out of range [0, "
     "0.95]"},
    {CLUSTER_WITH(", \"shell\": []"), SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.shell: expected an object, got an array"},
    {CLUSTER_WITH(", \"shell\": {\"layers\": 256, \"st\": 4096, \"su\": 64}"),
     SATF_ERR_ARGUMENT,
     "macro_clusters[0]: brings the scene's total HSV count (layers x st x "
     "su over all instances) to 67108864, over the limit of 50000000"},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]],"
     " \"a\": 1, \"shell\": {\"layers\": 200, \"st\": 4000, \"su\": 16}}},"
     " {\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]], \"a\": 1,"
     " \"shell\": {\"layers\": 200, \"st\": 4000, \"su\": 16}},"
     " \"instances\": [{}, {}, {}, {}]}]}",
     SATF_ERR_ARGUMENT,
     "macro_clusters[1]: brings the scene's total HSV count (layers x st x "
     "su over all instances) to 64000000, over"},
    {CLUSTER_WITH(", \"density\": {\"type\": \"cloud\"}"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.density.type: \"cloud\" is not one of "
     "\"procedural\", \"vdb\""},
    {CLUSTER_WITH(", \"density\": {\"layout\": \"wavy\"}"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.density.layout: \"wavy\" is not one of "
     "\"uniform\", \"clumped\", \"gradient\", \"holes\""},
    {CLUSTER_WITH(", \"density\": {\"strands\": 0}"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.density.strands: 0 is out of range [1, "
     "10000000]"},
    {CLUSTER_WITH(", \"density\": {\"layout\": \"clumped\", \"clumps\": 17}"),
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.density.clumps: 17 is out of range [1, 16]"},
    {CLUSTER_WITH(", \"density\": {\"strand_width\": 0}"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.density.strand_width: 0 is out of range "
     "(0, 0.5]"},
    {CLUSTER_WITH(", \"density\": {\"seed\": -1}"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.density.seed: -1 is out of range [0, "},
    {CLUSTER_WITH(", \"density\": {\"type\": \"vdb\"}"), SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.density.file: missing required key"},
    {CLUSTER_WITH(", \"density\": {\"type\": \"vdb\", \"file\": \"\"}"),
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.density.file: must not be an empty string"},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]],"
     " \"a\": 1}, \"instances\": []}]}",
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].instances: has 0 entries, expected 1 to 65536"},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]],"
     " \"a\": 1}, \"instances\": [{}, {\"matrix\": [1,0,0,0, 0,1,0,0, 0,0,1,0"
     ", 0,0,0,1], \"scale\": 2}]}]}",
     SATF_ERR_FORMAT,
     "macro_clusters[0].instances[1]: \"matrix\" cannot be combined with "
     "\"scale\""},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]],"
     " \"a\": 1}, \"instances\": [{\"matrix\": [1,0,0,0, 0,1,0,0, 0,0,0,0"
     ", 0,0,0,1]}]}]}",
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].instances[0].matrix: is singular (determinant 0"},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]],"
     " \"a\": 1}, \"instances\": [{\"matrix\": [1,0,0,0, 0,1,0,0, 0,0,1,0"
     ", 0,0,1,1]}]}]}",
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].instances[0].matrix: the last row must be [0, 0, 0, "
     "1]"},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]],"
     " \"a\": 1}, \"instances\": [{\"matrix\": [1,0,0]}]}]}",
     SATF_ERR_FORMAT,
     "macro_clusters[0].instances[0].matrix: expected an array of 16 "
     "numbers, got 3 entries"},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]],"
     " \"a\": 1}, \"instances\": [{\"rotate\": {\"axis\": [0,0,0], "
     "\"angle\": 30}}]}]}",
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].instances[0].rotate.axis: has zero length"},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]],"
     " \"a\": 1}, \"instances\": [{\"rotate\": {\"axis\": [0,0,1]}}]}]}",
     SATF_ERR_FORMAT,
     "macro_clusters[0].instances[0].rotate.angle: missing required key"},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]],"
     " \"a\": 1}, \"instances\": [{\"scale\": [1, 0, 1]}]}]}",
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].instances[0].scale: 0 is too close to zero"},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]],"
     " \"a\": 1}, \"instances\": [{\"translate\": [0, 2e6, 0]}]}]}",
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].instances[0].translate[1]: 2000000 is out of range "
     "[-1000000, 1000000]"},
    {SCENE_WITH(", \"material\": {\"model\": \"marschner\"}"),
     SATF_ERR_ARGUMENT, "material.model"},
    {SCENE_WITH(", \"material\": {\"melanin\": 1.2}"), SATF_ERR_ARGUMENT,
     "material.melanin: 1.2 is out of range [0, 1]"},
    {SCENE_WITH(", \"material\": {\"ior\": 1}"), SATF_ERR_ARGUMENT,
     "material.ior: 1 is out of range (1, 3]"},
    {SCENE_WITH(", \"material\": {\"absorption\": [0.1, -1, 0]}"),
     SATF_ERR_ARGUMENT, "material.absorption"},
    {SCENE_WITH(", \"material\": {\"k_dif\": -0.1}"), SATF_ERR_ARGUMENT,
     "material.k_dif: -0.1 is out of range [0, 100]"},
    {SCENE_WITH(", \"material\": {\"exponent_II\": 0}"), SATF_ERR_ARGUMENT,
     "material.exponent_II: 0 is out of range (0, 10000]"},
    {SCENE_WITH(", \"material\": {\"f_speII\": [0.5, 1.5, 0]}"),
     SATF_ERR_ARGUMENT, "material.f_speII[1]: 1.5 is out of range [0, 1]"},
    {SCENE_WITH(", \"material\": {\"shift\": 2}"), SATF_ERR_ARGUMENT,
     "material.shift: 2 is out of range [-1, 1]"},
    {SCENE_WITH(", \"material\": {\"noise\": null}"), SATF_ERR_FORMAT,
     "material.noise: expected a number, got null"},
    {SCENE_WITH(", \"effects\": {\"self_shadow\": 1}"), SATF_ERR_FORMAT,
     "effects.self_shadow: expected true or false, got a number"},
    {SCENE_WITH(", \"camera\": {\"fov_y\": 0}"), SATF_ERR_ARGUMENT,
     "camera.fov_y: 0 is out of range [0.1, 179]"},
    {SCENE_WITH(", \"camera\": {\"fov_y\": 180}"), SATF_ERR_ARGUMENT,
     "camera.fov_y: 180 is out of range [0.1, 179]"},
    {SCENE_WITH(", \"camera\": {\"position\": [1,2,3], \"target\": [1,2,3]}"),
     SATF_ERR_ARGUMENT, "camera.target: coincides with the camera position"},
    {SCENE_WITH(", \"camera\": {\"position\": [0,5,0], \"target\": [0,0,0]}"),
     SATF_ERR_ARGUMENT, "camera.up: is zero or parallel to the view direction"},
    {SCENE_WITH(", \"camera\": {\"near\": 10, \"far\": 5}"), SATF_ERR_ARGUMENT,
     "camera.far: 5 must be greater than near (10)"},
    {SCENE_WITH(", \"lights\": []"), SATF_ERR_ARGUMENT,
     "lights: has 0 entries, expected 1 to 8"},
    {SCENE_WITH(", \"lights\": [{\"type\": \"spot\"}]"), SATF_ERR_ARGUMENT,
     "lights[0].type: \"spot\" is not one of \"directional\", \"point\""},
    {SCENE_WITH(", \"lights\": [{\"type\": \"directional\"}]"), SATF_ERR_FORMAT,
     "lights[0].direction: missing required key"},
    {SCENE_WITH(", \"lights\": [{\"type\": \"point\"}]"), SATF_ERR_FORMAT,
     "lights[0].position: missing required key"},
    {SCENE_WITH(", \"lights\": [{\"direction\": [0,0,0]}]"), SATF_ERR_ARGUMENT,
     "lights[0].direction: has zero length"},
    {SCENE_WITH(", \"lights\": [{\"direction\": [0,0,1], \"intensity\": -1}]"),
     SATF_ERR_ARGUMENT, "lights[0].intensity: -1 is out of range [0, 1000000]"},
    {SCENE_WITH(", \"background\": [0, 0]"), SATF_ERR_FORMAT,
     "background: expected an array of 3 numbers, got 2 entries"},
    {SCENE_WITH(", \"database\": 5"), SATF_ERR_FORMAT,
     "database: expected a string, got a number"},
    {SCENE_WITH(", \"strands\": [\"a.hair\"]"), SATF_ERR_FORMAT,
     "strands: expected a string, got an array"},
    {SCENE_WITH(", \"image\": {\"width\": 0}"), SATF_ERR_ARGUMENT,
     "image.width: 0 is out of range [1, 16384]"},
    {SCENE_WITH(", \"image\": {\"height\": 1e9}"), SATF_ERR_ARGUMENT,
     "image.height: 1000000000 is out of range [1, 16384]"},
    {SCENE_WITH(", \"description\": [\"x\"]"), SATF_ERR_FORMAT,
     "description: expected a string, got an array"},
    {CLUSTER_WITH(", \"shell\": {\"layers\": 3, \"layers\": 4}"),
     SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.shell: key \"layers\" appears twice"},
    {SCENE_WITH(", \"database\": \"db\\u0000.exr\""), SATF_ERR_FORMAT,
     "\\u0000 (a NUL character) in a string"},
};
#define N_BAD (sizeof bad_cases / sizeof bad_cases[0])

static void test_malformed_cases(void **state) {
  (void)state;
  check_bad_cases(bad_cases, N_BAD, "bad.json");
}

/* An escaped backslash before "u0000" is text, not a NUL character. */
static void test_escaped_backslash_is_not_nul(void **state) {
  (void)state;
  satf_scene *scene =
      parse_ok(SCENE_WITH(", \"description\": \"a\\\\u0000\""), "ok.json");
  assert_string_equal(scene->description, "a\\u0000");
  satf_scene_destroy(scene);
}

static void test_exact_message(void **state) {
  (void)state;
  satf_scene *scene;
  satf_error err;
  const char *json = CLUSTER_WITH(", \"shell\": {\"layers\": 0}");
  assert_int_equal(
      satf_scene_parse(json, strlen(json), "samples/x.json", &scene, &err),
      SATF_ERR_ARGUMENT);
  assert_string_equal(err.message,
                      "samples/x.json: macro_clusters[0].prototype.shell."
                      "layers: 0 is out of range [1, 256]");
  /* Syntax errors: line:column of cJSON's error position. The stray ']'
   * is on line 3, after two spaces. */
  const char *multi = "{\n  \"macro_clusters\": [1,\n  ]\n}\n";
  assert_int_equal(
      satf_scene_parse(multi, strlen(multi), "m.json", &scene, &err),
      SATF_ERR_FORMAT);
  assert_string_equal(err.message, "m.json:3:3: malformed JSON near \"]\"");
  /* A NUL byte inside the text is reported where it is. */
  const char nul[] = "{\n \"a\":\0 1}";
  assert_int_equal(
      satf_scene_parse(nul, sizeof nul - 1, "n.json", &scene, &err),
      SATF_ERR_FORMAT);
  assert_string_equal(err.message, "n.json:2:6: NUL byte in the text");
  /* No name: messages say "<scene>" instead, never a crash. */
  assert_int_equal(satf_scene_parse("{}", 2, NULL, &scene, &err),
                   SATF_ERR_FORMAT);
  assert_string_equal(err.message,
                      "<scene>: macro_clusters: missing required key");
  /* NULL err is allowed. */
  assert_int_equal(satf_scene_parse("{}", 2, "x", &scene, NULL),
                   SATF_ERR_FORMAT);
  assert_null(scene);
}

static void test_load_errors(void **state) {
  (void)state;
  satf_scene *scene;
  satf_error err;
  assert_int_equal(satf_scene_load("/nonexistent/dir/s.json", &scene, &err),
                   SATF_ERR_IO);
  assert_null(scene);
  assert_non_null(strstr(err.message, "/nonexistent/dir/s.json: cannot open"));
}

/* ---- warnings ---- */

static void test_unknown_keys_warn(void **state) {
  (void)state;
  const char *json =
      "{\"macro_clusters\": [{\"prototype\": {\"trajectory\": "
      "[[0,0,0],[0,1,0]],"
      " \"a\": 0.5, \"shell\": {\"layres\": 12},"
      " \"density\": {\"layout\": \"uniform\", \"clumps\": 3}}}],"
      " \"zzqqxx\": 1, \"lights\": [{\"type\": \"point\", \"position\": "
      "[0,0,1],"
      " \"direction\": [0,0,1]}]}";
  satf_scene *scene = parse_ok(json, "w.json");
  assert_int_equal(satf_scene_warning_count(scene), 4);
  /* The typo did not silently set the value. */
  assert_int_equal(scene->macro_clusters[0].prototype.shell.layers, 3);
  const char *expected[4] = {
      "w.json: zzqqxx: unknown key (ignored)",
      "w.json: macro_clusters[0].prototype.shell.layres: unknown key "
      "(ignored); did you mean \"layers\"?",
      "w.json: macro_clusters[0].prototype.density.clumps: ignored: only "
      "used by layout \"clumped\"",
      "w.json: lights[0].direction: unknown key (ignored)"};
  for (int i = 0; i < 4; i++)
    assert_string_equal(satf_scene_warning(scene, i), expected[i]);
  assert_null(satf_scene_warning(scene, 4));
  assert_null(satf_scene_warning(scene, -1));
  satf_scene_destroy(scene);

  /* Hundreds of unknown keys: a bounded list plus a summary line. */
  size_t cap = 400 * 16 + 256;
  char *many = malloc(cap);
  assert_non_null(many);
  size_t o =
      (size_t)snprintf(many, cap, "{\"macro_clusters\": [%s]", MINIMAL_CLUSTER);
  for (int i = 0; i < 400; i++)
    o += (size_t)snprintf(many + o, cap - o, ", \"junk%d\": %d", i, i);
  snprintf(many + o, cap - o, "}");
  scene = parse_ok(many, "many.json");
  assert_int_equal(satf_scene_warning_count(scene), 257);
  assert_string_equal(satf_scene_warning(scene, 256),
                      "many.json: (root): 144 more warnings not shown");
  satf_scene_destroy(scene);
  free(many);
}

/* ---- paths ---- */

static void test_relative_paths(void **state) {
  (void)state;
  const char *json =
      "{\"macro_clusters\": [{\"prototype\": {\"trajectory\": "
      "[[0,0,0],[0,1,0]],"
      " \"a\": 1, \"density\": {\"type\": \"vdb\", \"file\": \"vol/c.vdb\","
      " \"grid\": \"rho\"}}}, {\"prototype\": {\"trajectory\": "
      "[[0,0,0],[0,1,0]],"
      " \"a\": 1, \"density\": {\"type\": \"vdb\", \"file\": "
      "\"/abs/d.vdb\"}}}],"
      " \"database\": \"../db/h.exr\", \"strands\": \"hair/s.hair\"}";
  satf_scene *scene = parse_ok(json, "/data/scenes/x.json");
  assert_string_equal(scene->database, "/data/scenes/../db/h.exr");
  assert_string_equal(scene->strands_file, "/data/scenes/hair/s.hair");
  assert_string_equal(scene->macro_clusters[0].prototype.density.vdb_file,
                      "/data/scenes/vol/c.vdb");
  assert_string_equal(scene->macro_clusters[0].prototype.density.vdb_grid,
                      "rho");
  assert_string_equal(scene->macro_clusters[1].prototype.density.vdb_file,
                      "/abs/d.vdb");
  satf_scene_destroy(scene);

  scene = parse_ok(json, "rel/x.json");
  assert_string_equal(scene->database, "rel/../db/h.exr");
  satf_scene_destroy(scene);
  scene = parse_ok(json, "x.json");
  assert_string_equal(scene->database, "../db/h.exr");
  satf_scene_destroy(scene);
  scene = parse_ok(json, "/x.json");
  assert_string_equal(scene->database, "/../db/h.exr");
  assert_string_equal(scene->macro_clusters[0].prototype.density.vdb_file,
                      "/vol/c.vdb");
  satf_error err;
  assert_int_equal(satf_scene_set_database(scene, "/cli/db.exr", &err),
                   SATF_OK);
  assert_string_equal(scene->database, "/cli/db.exr");
  assert_int_equal(satf_scene_set_database(scene, "", &err), SATF_ERR_ARGUMENT);
  assert_string_equal(scene->database, "/cli/db.exr");
  satf_scene_destroy(scene);

  /* Loaded from a file: relative to the file's directory. */
  const char *tmp = getenv("SATF_TEST_TMP");
  char path[1024], want[1100];
  snprintf(path, sizeof path, "%s/scene_paths.json", tmp ? tmp : ".");
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  fputs(SCENE_WITH(", \"database\": \"sub/db.exr\""), f);
  fclose(f);
  assert_int_equal(satf_scene_load(path, &scene, &err), SATF_OK);
  snprintf(want, sizeof want, "%s/sub/db.exr", tmp ? tmp : ".");
  assert_string_equal(scene->database, want);
  assert_string_equal(scene->name, path);
  satf_scene_destroy(scene);
  remove(path);
}

/* ---- instance transforms ---- */

static satf_scene *scene_with_instances(const char *instances) {
  char json[1024];
  snprintf(json, sizeof json,
           "{\"macro_clusters\": [{\"prototype\": {\"trajectory\": "
           "[[0,0,0],[0,1,0]], \"a\": 1}, \"instances\": [%s]}]}",
           instances);
  return parse_ok(json, "t.json");
}

static void apply(const satf_scene *scene, int i, float x, float y, float z,
                  float out[3]) {
  const float p[3] = {x, y, z};
  satf_scene_instance_apply(&scene->macro_clusters[0].instances[i], p, out);
}

/* The strand width the density assumes: strand_width x the cluster radius
 * x the instance's scale, the median over the instances. */
static void test_density_strand_width(void **state) {
  (void)state;
  satf_scene *one = scene_with_instances("{}");
  assert_float_equal(satf_scene_density_strand_width(one), 0.03f, 1e-7f);
  satf_scene_destroy(one);
  satf_scene *three =
      scene_with_instances("{\"scale\": 2}, {\"scale\": 3}, {}");
  assert_float_equal(satf_scene_density_strand_width(three), 0.06f, 1e-6f);
  satf_scene_destroy(three);
  satf_scene *tracks = parse_ok(
      "{\"macro_clusters\": [{\"prototype\": {\"trajectory\": "
      "[[0,0,0],[0,1,0]], \"a\": 1, \"density\": {\"type\": \"tracks\", "
      "\"slices\": 2, \"tracks\": [[0, 0, 0, 0, 0]]}}}]}",
      "t.json");
  assert_true(satf_scene_density_strand_width(tracks) == 0.0f);
  satf_scene_destroy(tracks);
}

static void test_instance_transforms(void **state) {
  (void)state;
  satf_scene *scene = scene_with_instances(
      "{\"translate\": [1,2,3], \"rotate\": {\"axis\": [0,0,1], \"angle\": 90},"
      " \"scale\": 2},"
      "{\"translate\": [-1,0,1], \"rotate\": {\"axis\": [0,5,0], \"angle\": "
      "90}, \"scale\": [2,3,4]},"
      "{\"rotate\": {\"axis\": [1,0,0], \"angle\": -90}},"
      "{\"matrix\": [0,-1,0,5, 1,0,0,6, 0,0,2,7, 0,0,0,1]},"
      "{},"
      "{\"rotate\": {\"axis\": [1,1,1], \"angle\": 120}}");
  assert_int_equal(scene->macro_clusters[0].n_instances, 6);
  assert_int_equal(satf_scene_cluster_count(scene), 6);
  float q[3];
  /* Scale (1,0,0) -> (2,0,0); +90 deg about z -> (0,2,0); translate ->
   * (1,4,3). */
  apply(scene, 0, 1, 0, 0, q);
  assert_near(q[0], 1, 1e-5);
  assert_near(q[1], 4, 1e-5);
  assert_near(q[2], 3, 1e-5);
  /* Scale (1,2,3) by (2,3,4) -> (2,6,12); +90 deg about y maps (x,y,z) to
   * (z,y,-x) -> (12,6,-2); translate -> (11,6,-1). */
  apply(scene, 1, 1, 2, 3, q);
  assert_near(q[0], 11, 1e-5);
  assert_near(q[1], 6, 1e-5);
  assert_near(q[2], -1, 1e-5);
  /* -90 deg about x maps (x,y,z) to (x,z,-y): (1,2,3) -> (1,3,-2). */
  apply(scene, 2, 1, 2, 3, q);
  assert_near(q[0], 1, 1e-5);
  assert_near(q[1], 3, 1e-5);
  assert_near(q[2], -2, 1e-5);
  /* Row-major matrix: (1,2,3) -> (-2+5, 1+6, 6+7). */
  apply(scene, 3, 1, 2, 3, q);
  assert_near(q[0], 3, 0);
  assert_near(q[1], 7, 0);
  assert_near(q[2], 13, 0);
  /* {} is the identity. */
  apply(scene, 4, 1, 2, 3, q);
  assert_true(q[0] == 1.0f && q[1] == 2.0f && q[2] == 3.0f);
  /* 120 deg about (1,1,1) cycles the axes: x -> y -> z -> x. */
  apply(scene, 5, 1, 2, 3, q);
  assert_near(q[0], 3, 1e-5);
  assert_near(q[1], 1, 1e-5);
  assert_near(q[2], 2, 1e-5);
  /* In-place use. */
  q[0] = 1, q[1] = 0, q[2] = 0;
  satf_scene_instance_apply(&scene->macro_clusters[0].instances[0], q, q);
  assert_near(q[1], 4, 1e-5);

  /* World bounds: prototype segment (0,0,0)-(0,1,0) grown by a = 1 is
   * [-1,1] x [-1,2] x [-1,1]; instance 3 maps it to x in [3,6],
   * y in [5,7], z in [5,9], which holds the maximum x, y and z. Instance 1
   * (scale 2,3,4, then +90 about y, then (-1,0,1)) spans x in [-5,3]. */
  float lo[3], hi[3];
  satf_scene_bounds(scene, lo, hi);
  assert_near(hi[0], 6, 1e-5);
  assert_near(hi[1], 7, 1e-5);
  assert_near(hi[2], 9, 1e-5);
  assert_near(lo[0], -5, 1e-5);
  satf_scene_destroy(scene);
}

/* ---- replay of generated malformed inputs through the fuzz target ---- */

static int count_loaded(const char *text, size_t len) {
  return satf_fuzz_scene_one((const uint8_t *)text, len);
}

static void test_fuzz_replay(void **state) {
  (void)state;
  int loaded = 0, rejected = 0;
  satf_rng rng;
  satf_rng_seed(&rng, 2006, 0);
  for (size_t i = 0; i < N_SAMPLES; i++) {
    char path[512];
    size_t len;
    snprintf(path, sizeof path, "%s/%s", SATF_SAMPLES_DIR, samples[i].file);
    char *text = (char *)test_read_file(path, &len);
    assert_int_equal(count_loaded(text, len), 1);
    /* Truncations: everything before the closing brace is incomplete. */
    size_t last = len;
    while (last > 0 && text[last - 1] != '}')
      last--;
    for (size_t cut = 0; cut + 1 < last; cut += (cut < 64 ? 1 : 7))
      assert_int_equal(count_loaded(text, cut), 0);
    /* Random byte flips. */
    char *copy = malloc(len);
    assert_non_null(copy);
    for (int m = 0; m < 1500; m++) {
      memcpy(copy, text, len);
      int flips = 1 + (int)satf_rng_below(&rng, 4);
      for (int f = 0; f < flips; f++)
        copy[satf_rng_below(&rng, (uint32_t)len)] =
            (char)satf_rng_below(&rng, 256);
      if (count_loaded(copy, len))
        loaded++;
      else
        rejected++;
    }
    /* Every number in the file replaced by 1e400, and every string value
     * by a number: each must be rejected. */
    char *edit = malloc(len + 16);
    assert_non_null(edit);
    for (size_t p = 0; p < len; p++) {
      int starts_number =
          (text[p] == '-' || (text[p] >= '0' && text[p] <= '9')) &&
          (p == 0 || strchr("[,: \n", text[p - 1]));
      int starts_string = text[p] == '"';
      if (!starts_number && !starts_string)
        continue;
      size_t q = p + 1;
      if (starts_number)
        while (q < len && strchr("0123456789.eE+-", text[q]))
          q++;
      else
        while (q < len && text[q] != '"')
          q++, q += (text[q - 1] == '\\');
      if (starts_string) {
        size_t after = q + 1;
        while (after < len && text[after] == ' ')
          after++;
        if (after < len && text[after] == ':') { /* a key, not a value */
          p = q;
          continue;
        }
        q++;
      }
      const char *with = starts_number ? "1e400" : "7";
      size_t nw = strlen(with);
      memcpy(edit, text, p);
      memcpy(edit + p, with, nw);
      memcpy(edit + p + nw, text + q, len - q);
      satf_error err;
      satf_scene *scene;
      satf_status s =
          satf_scene_parse(edit, p + nw + len - q, "edit.json", &scene, &err);
      if (s == SATF_OK) {
        fprintf(stderr, "%s: replacing offset %zu was accepted\n",
                samples[i].file, p);
        fail();
      }
      assert_non_null(
          strstr(err.message, starts_number ? "too large" : "got a number"));
      assert_int_equal(count_loaded(edit, p + nw + len - q), 0);
      p = q - 1;
    }
    free(edit);
    free(copy);
    free(text);
  }
  /* Flips that land in a digit or in whitespace keep a file valid; most
   * flips break it. */
  assert_true(rejected > loaded);
  assert_true(loaded > 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_samples_match_table1),
      cmocka_unit_test(test_hairstyle_hierarchy),
      cmocka_unit_test(test_defaults),
      cmocka_unit_test(test_explicit_values),
      cmocka_unit_test(test_malformed_cases),
      cmocka_unit_test(test_exact_message),
      cmocka_unit_test(test_escaped_backslash_is_not_nul),
      cmocka_unit_test(test_load_errors),
      cmocka_unit_test(test_unknown_keys_warn),
      cmocka_unit_test(test_relative_paths),
      cmocka_unit_test(test_instance_transforms),
      cmocka_unit_test(test_density_strand_width),
      cmocka_unit_test(test_fuzz_replay),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
