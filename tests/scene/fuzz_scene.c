/* fuzz_scene.c - libFuzzer target for satf_scene_parse. Any byte string
 * must either load into a scene that satisfies every documented limit or
 * fail with a message naming the input; anything else aborts. An animated
 * scene's snapshots (satf/anim.h) at and around its frame range must
 * satisfy the same limits or fail with such a message. The same check runs
 * in test_scene on a generated corpus, without libFuzzer. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/scene.h"

int satf_fuzz_scene_one(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define FUZZ_NAME "fuzz/scene.json"

static void require(int ok, const char *what) {
  if (!ok) {
    fprintf(stderr, "fuzz_scene: invariant broken: %s\n", what);
    abort();
  }
}

static int finite3(const float *v) {
  return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static void check_curve(const satf_scene_curve *c, int positive) {
  require(c->count >= 1 && c->count <= SATF_SCENE_MAX_CONTROL_POINTS,
          "curve size");
  for (int i = 0; i < c->count; i++) {
    require(isfinite(c->values[i]), "curve value finite");
    if (positive)
      require(c->values[i] > 0.0f, "radius positive");
  }
}

static void check_scene(const satf_scene *scene) {
  require(scene->n_macro_clusters >= 1, "macro-cluster count");
  require(satf_scene_hsv_count(scene) <= SATF_SCENE_MAX_HSV, "HSV limit");
  require(satf_scene_cluster_count(scene) <= SATF_SCENE_MAX_CLUSTERS,
          "cluster limit");
  for (int i = 0; i < scene->n_macro_clusters; i++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[i];
    const satf_scene_cluster *c = &mc->prototype;
    require(c->n_points >= 2, "trajectory size");
    for (int p = 0; p < c->n_points; p++)
      require(finite3(c->trajectory + 3 * p), "trajectory finite");
    check_curve(&c->a, 1);
    check_curve(&c->b, 1);
    check_curve(&c->twist, 0);
    int n = satf_scene_cluster_curve_count(c);
    require((c->a.count == 1 || c->a.count == n) &&
                (c->b.count == 1 || c->b.count == n) &&
                (c->twist.count == 1 || c->twist.count == n),
            "a, b, twist share one control count");
    require(c->density.type != SATF_SCENE_DENSITY_PROCEDURAL ||
                (c->density.clumps >= 1 &&
                 c->density.clumps <= SATF_SCENE_MAX_CLUMPS &&
                 c->density.holes >= 1 &&
                 c->density.holes <= SATF_SCENE_MAX_CLUMPS &&
                 c->density.strands >= 1 && c->density.strand_width > 0.0f),
            "procedural density parameters");
    require(c->shell.layers >= 1 && c->shell.layers <= SATF_SCENE_MAX_LAYERS,
            "layers");
    require(c->shell.su >= SATF_SCENE_MIN_SU, "su");
    require(c->shell.core >= 0.0f && c->shell.core <= 0.95f, "core");
    require(c->density.type != SATF_SCENE_DENSITY_VDB ||
                (c->density.vdb_file && c->density.vdb_grid),
            "vdb paths");
    require(mc->n_instances >= 1, "instance count");
    for (int j = 0; j < mc->n_instances; j++) {
      for (int k = 0; k < 16; k++)
        require(isfinite(mc->instances[j].m[k]), "instance finite");
      const float *m = mc->instances[j].m;
      require(fabsf(m[12]) <= 1e-6f && fabsf(m[13]) <= 1e-6f &&
                  fabsf(m[14]) <= 1e-6f && fabsf(m[15] - 1.0f) <= 1e-6f,
              "affine");
    }
  }
  require(scene->n_lights >= 1 && scene->n_lights <= SATF_SCENE_MAX_LIGHTS,
          "light count");
  require(finite3(scene->camera.position) && finite3(scene->camera.target),
          "camera finite");
  require(scene->image.width >= 1 && scene->image.height >= 1, "image size");
  for (int i = 0; i < satf_scene_warning_count(scene); i++) {
    const char *w = satf_scene_warning(scene, i);
    require(w && strncmp(w, FUZZ_NAME ": ", strlen(FUZZ_NAME) + 2) == 0,
            "warning names the input");
  }
  require(satf_scene_warning(scene, satf_scene_warning_count(scene)) == NULL,
          "warning index past the end");
}

static void check_snapshot(const satf_scene *scene, double frame) {
  satf_scene *snap = (satf_scene *)(uintptr_t)1; /* must be overwritten */
  satf_error err;
  satf_error_clear(&err);
  satf_status s = satf_scene_at_frame(scene, frame, &snap, &err);
  if (s != SATF_OK) {
    require(snap == NULL, "no snapshot on failure");
    require(err.status == s, "snapshot error status matches");
    require(strncmp(err.message, FUZZ_NAME " at frame ",
                    strlen(FUZZ_NAME) + 10) == 0,
            "snapshot error names the input and the frame");
    return;
  }
  require(snap != NULL, "snapshot on success");
  require(!satf_scene_is_animated(snap), "a snapshot is static");
  require(satf_scene_warning_count(snap) == 0, "a snapshot has no warnings");
  check_scene(snap);
  require(satf_scene_hsv_count(snap) == satf_scene_hsv_count(scene) &&
              satf_scene_cluster_count(snap) ==
                  satf_scene_cluster_count(scene) &&
              snap->n_lights == scene->n_lights,
          "a snapshot keeps the counts");
  for (int i = 0; i < scene->n_macro_clusters; i++)
    require(satf_scene_prototype_is_animated(scene, i) ||
                satf_scene_prototype_equal(&snap->macro_clusters[i].prototype,
                                           &scene->macro_clusters[i].prototype),
            "an unanimated prototype is the static one");
  satf_scene_destroy(snap);
}

static void check_animation(const satf_scene *scene) {
  int first, last;
  if (!satf_scene_frame_range(scene, &first, &last)) {
    require(first == 0 && last == 0 && satf_scene_fps(scene) == 0.0,
            "a static scene has no frame range");
    return;
  }
  require(first <= last, "frame range ordered");
  require(satf_scene_fps(scene) > 0.0 &&
              satf_scene_fps(scene) <= SATF_SCENE_MAX_FPS,
          "fps in range");
  const double frames[5] = {first - 1.0, first, 0.5 * (first + last) + 0.25,
                            last, last + 1.0};
  for (int i = 0; i < 5; i++)
    check_snapshot(scene, frames[i]);
}

/* The writer gives back what was read: the text, read from the same
 * directory ("fuzz", that of FUZZ_NAME), parses into an equal scene (inputs
 * with warnings may hold values the format drops, such as the parameters of
 * another layout, and are left out). */
static void check_written(const satf_scene *scene) {
  if (satf_scene_warning_count(scene) > 0)
    return;
  char *text = NULL;
  satf_error err;
  require(satf_scene_to_json(scene, "fuzz", &text, &err) == SATF_OK,
          "the scene is written");
  satf_scene *again = NULL;
  require(satf_scene_parse(text, strlen(text), FUZZ_NAME, &again, &err) ==
              SATF_OK,
          "the written scene parses");
  require(satf_scene_equal(scene, again), "the written scene is the same");
  satf_scene_destroy(again);
  free(text);
}

/* Returns 1 when the input loaded, 0 when it was rejected. */
int satf_fuzz_scene_one(const uint8_t *data, size_t size) {
  satf_scene *scene = (satf_scene *)(uintptr_t)1; /* must be overwritten */
  satf_error err;
  satf_error_clear(&err);
  satf_status s =
      satf_scene_parse((const char *)data, size, FUZZ_NAME, &scene, &err);
  if (s == SATF_OK) {
    require(scene != NULL, "scene on success");
    check_scene(scene);
    check_animation(scene);
    check_written(scene);
    satf_scene_destroy(scene);
    return 1;
  }
  require(scene == NULL, "no scene on failure");
  require(err.status == s, "error status matches");
  require(strncmp(err.message, FUZZ_NAME, strlen(FUZZ_NAME)) == 0,
          "error names the input");
  require(strlen(err.message) > strlen(FUZZ_NAME) + 4, "error says what");
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  satf_fuzz_scene_one(data, size);
  return 0;
}
