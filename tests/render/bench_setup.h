/* bench_setup.h - what the frame benchmarks (bench_frames, bench_dom)
 * open before they measure: a database, a scene, a headless GL context of
 * w x h and a renderer of the scene; any failure ends the program with a
 * message naming what failed. */
#ifndef SATF_TESTS_BENCH_SETUP_H
#define SATF_TESTS_BENCH_SETUP_H

#include <stdio.h>
#include <stdlib.h>

#include "satf/db.h"
#include "satf/gl.h"
#include "satf/render.h"
#include "satf/scene.h"

typedef struct bench_setup {
  satf_db *db;
  satf_scene *scene;
  satf_gl_context *ctx;
  satf_renderer *r;
} bench_setup;

static inline void bench_fail(const char *prog, const char *what,
                              const satf_error *err) {
  fprintf(stderr, "%s: %s: %s\n", prog, what, err ? err->message : "");
  exit(1);
}

/* w or h 0: the scene's image size (640 x 480 where it gives none). */
static inline bench_setup bench_open(const char *prog, const char *db_path,
                                     const char *scene_path, int w, int h) {
  bench_setup b = {NULL, NULL, NULL, NULL};
  satf_error err;
  if (satf_db_read(db_path, &b.db, &err) != SATF_OK)
    bench_fail(prog, db_path, &err);
  if (satf_scene_load(scene_path, &b.scene, &err) != SATF_OK)
    bench_fail(prog, scene_path, &err);
  if (w <= 0 || h <= 0) {
    w = b.scene->image.width > 0 ? b.scene->image.width : 640;
    h = b.scene->image.height > 0 ? b.scene->image.height : 480;
  }
  if (satf_gl_context_create_headless(w, h, &b.ctx, &err) != SATF_OK)
    bench_fail(prog, "GL", &err);
  if (satf_renderer_create(b.scene, b.db, w, h, 0, &b.r, &err) != SATF_OK)
    bench_fail(prog, "renderer", &err);
  return b;
}

static inline void bench_close(bench_setup *b) {
  satf_renderer_destroy(b->r);
  satf_gl_context_destroy(b->ctx);
  satf_scene_destroy(b->scene);
  satf_db_destroy(b->db);
}

#endif
