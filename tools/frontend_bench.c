/* frontend_bench.c - the Table 1 benchmark (frontend.h): an orbit of the
 * camera or the animation played, timed frame by frame, and its row. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "frontend.h"
#include "satf/common.h"
#include "satf/math.h"

void satf_frontend_table_header(FILE *out) {
  fprintf(out, "%-16s %4s %4s %6s %6s %7s %7s %7s %7s %7s %7s\n", "scene", "C#",
          "L#", "S#(K)", "H#(K)", "I ms", "C ms", "M ms", "L ms", "S ms",
          "FPS");
}

void satf_frontend_table_row(FILE *out, const char *name,
                             const satf_render_stats *s,
                             const satf_frame_timing *m, double fps) {
  fprintf(
      out, "%-16s %4ld %4ld %6.1f %6.1f %7.1f %7.1f %7.1f %7.1f %7.1f %7.1f\n",
      name, s->clusters, s->layers, s->strands / 1000.0, s->hsvs / 1000.0,
      m->index_ms, m->maps_ms, m->upload_ms, m->lighting_ms, m->shadow_ms, fps);
}

satf_status satf_frontend_frame_range(const satf_scene *scene, const char *text,
                                      int *first, int *last, satf_error *err) {
  char tail = 0;
  if (!strcmp(text, "all")) {
    satf_scene_frame_range(scene, first, last);
  } else if (sscanf(text, "%d-%d%c", first, last, &tail) != 2) {
    if (sscanf(text, "%d%c", first, &tail) != 1)
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "--frames: expected A-B, N or all, got '%s'", text);
    *last = *first;
  }
  /* Frames outside the scene's own would render a held pose under names
   * that no frame of the scene has (f_-001), so they are refused. */
  int lo = 0, hi = 0;
  int animated = satf_scene_frame_range(scene, &lo, &hi);
  if (*first > *last || *first < 0 || (animated && (*first < lo || *last > hi)))
    return animated ? satf_error_set(err, SATF_ERR_ARGUMENT,
                                     "--frames: '%s' is not a range A-B with "
                                     "A <= B within the scene's frames %d-%d",
                                     text, lo, hi)
                    : satf_error_set(err, SATF_ERR_ARGUMENT,
                                     "--frames: '%s' is not a range A-B with "
                                     "0 <= A <= B",
                                     text);
  return SATF_OK;
}

/* Rotates the eye about the up axis through the target (Rodrigues). */
static void orbit(satf_scene_camera *cam, const satf_scene_camera *start,
                  float angle) {
  float v[3], kx[3];
  for (int a = 0; a < 3; a++)
    v[a] = start->position[a] - start->target[a];
  float c = cosf(angle), s = sinf(angle);
  float kv = satf_dot3f(start->up, v);
  satf_cross3f(start->up, v, kx);
  for (int a = 0; a < 3; a++)
    cam->position[a] =
        start->target[a] + v[a] * c + kx[a] * s + start->up[a] * kv * (1 - c);
}

void satf_frontend_walk_begin(satf_frontend_walk *w, satf_renderer *r,
                              const satf_scene *scene, long frames) {
  memset(w, 0, sizeof *w);
  w->r = r;
  w->scene = scene;
  w->start = *satf_renderer_camera(r);
  w->frames = frames > 0 ? frames : 1;
  w->animated = satf_scene_frame_range(scene, &w->first, &w->last);
}

satf_status satf_frontend_walk_step(satf_frontend_walk *w, long f,
                                    satf_error *err) {
  if (!w->animated) {
    orbit(satf_renderer_camera(w->r), &w->start,
          SATF_TWO_PI_F * (float)f / (float)w->frames);
    return SATF_OK;
  }
  /* play the animation: moving clusters are rebuilt */
  satf_scene *next = NULL;
  double frame = w->first + (double)(f % (w->last - w->first + 1));
  satf_status st = satf_scene_at_frame(w->scene, frame, &next, err);
  if (st == SATF_OK)
    st = satf_renderer_set_scene(w->r, next, NULL, err);
  satf_scene_destroy(w->snap);
  w->snap = next;
  return st;
}

void satf_frontend_walk_end(satf_frontend_walk *w, int ok) {
  if (w->snap) {
    satf_error ignore;
    satf_renderer_set_scene(w->r, w->scene, NULL, &ignore);
    satf_scene_destroy(w->snap);
    w->snap = NULL;
  }
  if (ok)
    *satf_renderer_camera(w->r) = w->start;
}

satf_status satf_frontend_bench(satf_renderer *r, const satf_scene *scene,
                                long frames, satf_frontend_present_fn present,
                                void *ctx, satf_frame_timing *mean, double *fps,
                                satf_error *err) {
  satf_frame_timing t;
  memset(mean, 0, sizeof *mean);
  satf_status st = satf_renderer_render(r, SATF_AOV_BEAUTY, &t, err);
  if (st == SATF_OK && present)
    st = present(ctx, err);
  if (st != SATF_OK)
    return st;
  satf_frontend_walk w;
  satf_frontend_walk_begin(&w, r, scene, frames);
  double b0 = satf_now_seconds(), n = (double)frames;
  for (long f = 0; f < frames && st == SATF_OK; f++) {
    double s0 = satf_now_seconds();
    st = satf_frontend_walk_step(&w, f, err);
    double s1 = satf_now_seconds();
    if (st == SATF_OK)
      st = satf_renderer_render(r, SATF_AOV_BEAUTY, &t, err);
    if (st == SATF_OK && present)
      st = present(ctx, err);
    if (st != SATF_OK)
      break;
    /* interpolating the frame and rebuilding moving clusters counts as
     * index calculation (Table 1's I) */
    t.index_ms += 1e3 * (s1 - s0);
    mean->index_ms += t.index_ms / n;
    mean->maps_ms += t.maps_ms / n;
    mean->upload_ms += t.upload_ms / n;
    mean->lighting_ms += t.lighting_ms / n;
    mean->shadow_ms += t.shadow_ms / n;
  }
  *fps = n / (satf_now_seconds() - b0);
  satf_frontend_walk_end(&w, st == SATF_OK);
  return st;
}
