/* frontend.h - what satf-render and satf-view share: loading a scene with
 * its database, the effect switches of the paper's Fig. 4, frame ranges,
 * the PNG preview, and the Table 1 benchmark and row. */
#ifndef SATF_TOOLS_FRONTEND_H
#define SATF_TOOLS_FRONTEND_H

#include <stdio.h>

#include "satf/common.h"
#include "satf/import.h"
#include "satf/render.h"

typedef struct satf_frontend {
  satf_scene *scene;
  satf_db *db;
  /* --strands: the scene's source strands (satf_frontend_load_strands),
   * drawn instead of the clusters; NULL otherwise */
  satf_strand_set *strands;
  /* --strand-width: > 0 replaces the file's thickness; -1 ("density"):
   * the width the clusters' density assumes */
  float strand_width;
  /* --sparse-strands N: clusters of at most N strands drawn as strands
   * (satf_renderer_set_sparse_strands); -1: the renderer's default */
  int sparse_strands;
  const char *db_path;    /* where the database came from, for messages */
  int db_from_scene;      /* db_path is the scene's "database", not --db */
  char *db_path_owned;    /* db_path when the frontend chose it (freed) */
  const char *scene_path; /* as given, for messages */
  double budget;          /* --memory-budget in bytes, the default applied */
  /* satf_render_memory_estimate's total at satf_frontend_check_memory */
  double memory_estimate;
} satf_frontend;

/* Loads SCENE (printing its warnings to stderr) and the database (db_path,
 * or the scene's "database"); a zero *width takes the scene's image size.
 * Refuses, before the database is read, a scene whose
 * satf_render_memory_estimate without it is over `budget` bytes (0: half
 * the machine's memory), naming the largest part. On failure prints
 * "PROG: reason" and returns non-OK. */
satf_status satf_frontend_load(const char *prog, const char *scene_path,
                               const char *db_path, double budget, long *width,
                               long *height, satf_frontend *fe);
/* The same refusal once the database is known (after
 * satf_frontend_set_shading, which may take the fibre one), counting it
 * and, for maps SATF_MAPS_GPU, the GPU's maps; sets fe->memory_estimate.
 * On failure prints "PROG: reason" and returns non-OK. */
satf_status satf_frontend_check_memory(const char *prog, satf_frontend *fe,
                                       long width, long height,
                                       satf_maps_mode maps);
/* satf_renderer_create with a progress bar on stderr for the set-up
 * (clusters built), unless quiet. */
satf_status satf_frontend_create_renderer(const satf_frontend *fe, int width,
                                          int height, int threads, int quiet,
                                          satf_renderer **out, satf_error *err);
/* --memory-budget GB: 1 if arg was it (sets *bytes), -1 after printing a
 * bad value, 0 otherwise. */
int satf_frontend_budget_flag(satf_cli_args *it, double *bytes);
extern const char *const satf_frontend_budget_help;

/* --strands: reads the scene's source strands (its "strands" key, a
 * cyHair .hair file in scene coordinates, which satf-import writes beside
 * the scene) into fe->strands (fe->strand_width is applied when they are
 * handed to the renderer). A scene without strands is an error. On failure
 * prints "PROG: reason" and returns non-OK. */
satf_status satf_frontend_load_strands(const char *prog, satf_frontend *fe);
/* Has r draw fe->strands instead of the clusters (the strand reference
 * path, satf_renderer_set_strands); nothing without them. */
satf_status satf_frontend_apply_strands(satf_renderer *r,
                                        const satf_frontend *fe,
                                        satf_error *err);
/* --shading kk|physical: the shading model for this run, whatever the
 * scene's material says (SATF_MATERIAL_*); returns 1 if arg was it, -1
 * after printing a bad value, 0 otherwise. */
int satf_frontend_shading_flag(satf_cli_args *it, int *model);
/* Sets the scene's shading model (model < 0: keeps the scene's) and checks
 * that the database holds the records it needs; on failure prints
 * "PROG: reason" and returns non-OK. */
satf_status satf_frontend_set_shading(const char *prog, satf_frontend *fe,
                                      int model);
extern const char *const satf_frontend_shading_help;
/* --sparse-strands N (0 to SATF_SPARSE_STRANDS_MAX); returns 1 if arg was
 * it, -1 after printing a bad value, 0 otherwise. */
int satf_frontend_sparse_flag(satf_cli_args *it, int *max_strands);
extern const char *const satf_frontend_sparse_help;

/* Applies --strands or --strand-width W|density (setting *on, *width; -1
 * for density); returns 1 if arg was one of them, -1 after printing a bad
 * value. */
int satf_frontend_strand_flag(satf_cli_args *it, int *on, float *width);
extern const char *const satf_frontend_strand_help;

/* Turns off the effects cleared in `off` and sets the compositing mode. */
void satf_frontend_apply(satf_renderer *r, const satf_scene_effects *off,
                         int composite);
/* Says on stderr why the maps fell back to the CPU's, if they did
 * (satf_renderer_maps_note); r may be NULL. */
void satf_frontend_maps_note(const char *prog, const satf_renderer *r);
void satf_frontend_free(satf_frontend *fe);

/* Applies a --no-EFFECT flag; returns 1 if arg was one. */
int satf_frontend_effect_flag(const char *arg, satf_scene_effects *e);
extern const char *const satf_frontend_effect_help;

/* Parses --composite's value ("exact" or "ordered"); -1 if neither. */
int satf_frontend_composite(const char *value);

/* Table 1 of the paper: C#, L#, S#, H#, then ms for I, C, M, L, S and FPS. */
void satf_frontend_table_header(FILE *out);
void satf_frontend_table_row(FILE *out, const char *name,
                             const satf_render_stats *s,
                             const satf_frame_timing *mean, double fps);

/* Parses --frames' value: "A-B", "N" or "all" (the scene's range). */
satf_status satf_frontend_frame_range(const satf_scene *scene, const char *text,
                                      int *first, int *last, satf_error *err);

/* Called after each benchmark frame is rendered, e.g. to show it in a
 * window (satf-view); its time counts in the frame rate. */
typedef satf_status (*satf_frontend_present_fn)(void *ctx, satf_error *err);

/* The frames of Table 1's measurement, one at a time: frame f of n shows
 * the scene's animation frame (looping over its range) or, for a static
 * scene, the camera a fraction f / n of the way round its target. Begin
 * keeps the renderer's camera; end shows `scene` from it again. Two walks
 * over two renderers, stepped in turn, time both under the same load
 * (tests/render/bench_shading). */
typedef struct satf_frontend_walk {
  satf_renderer *r;
  const satf_scene *scene;
  satf_scene_camera start;
  long frames;
  int animated, first, last;
  satf_scene *snap; /* the animation frame shown (owned) */
} satf_frontend_walk;
void satf_frontend_walk_begin(satf_frontend_walk *w, satf_renderer *r,
                              const satf_scene *scene, long frames);
satf_status satf_frontend_walk_step(satf_frontend_walk *w, long f,
                                    satf_error *err);
/* ok: restores the camera too (not after a failed frame) */
void satf_frontend_walk_end(satf_frontend_walk *w, int ok);

/* Table 1's measurement: one warm-up frame, then `frames` timed frames of
 * the scene's animation, or, for a static scene, of the camera orbiting its
 * target once, each followed by present(ctx) when present is not NULL.
 * Fills the mean stage times and the frame rate; on success the renderer
 * shows `scene` from its original camera again. */
satf_status satf_frontend_bench(satf_renderer *r, const satf_scene *scene,
                                long frames, satf_frontend_present_fn present,
                                void *ctx, satf_frame_timing *mean, double *fps,
                                satf_error *err);

#endif
