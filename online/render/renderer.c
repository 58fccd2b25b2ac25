/* renderer.c - owns the renderer's public API (satf/render.h): creating
 * and destroying it, switching scenes and image sizes, its interactive
 * state, and rendering frames and images by running the per-frame CPU work
 * (frame.c) and the GPU passes (passes.c) in order. */
#include "mat4.h"
#include "renderer_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "shaders.h"

const char *satf_aov_name(satf_aov aov) {
  static const char *names[] = {"beauty", "diffuse", "specI",
                                "specII", "shadow",  "alpha"};
  return aov < SATF_AOV_COUNT ? names[aov] : "unknown";
}

static satf_status check_size(int width, int height, satf_error *err) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "image size %dx%d", width,
                          height);
  return SATF_OK;
}

/* The scene's camera, lights and bounds (the state an animation moves). */
static void take_view(satf_renderer *r, const satf_scene *scene) {
  r->camera = scene->camera;
  r->nlights = scene->n_lights < SATF_SCENE_MAX_LIGHTS ? scene->n_lights
                                                       : SATF_SCENE_MAX_LIGHTS;
  memcpy(r->lights, scene->lights,
         (size_t)r->nlights * sizeof(satf_scene_light));
  satf_scene_bounds(scene, r->lo, r->hi);
}

satf_status satf_renderer_create(const satf_scene *scene, const satf_db *db,
                                 int width, int height, int threads,
                                 satf_renderer **out, satf_error *err) {
  return satf_renderer_create_progress(scene, db, width, height, threads, NULL,
                                       NULL, out, err);
}

satf_status
satf_renderer_create_progress(const satf_scene *scene, const satf_db *db,
                              int width, int height, int threads,
                              satf_progress_fn progress, void *progress_ctx,
                              satf_renderer **out, satf_error *err) {
  *out = NULL;
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 43)
    return satf_error_set(err, SATF_ERR_GL,
                          "the renderer needs OpenGL 4.3 (shader storage "
                          "buffers and image atomics); this context has %d.%d",
                          major, minor);
  satf_status st = check_size(width, height, err);
  if (st != SATF_OK)
    return st;
  satf_renderer *r = calloc(1, sizeof *r);
  if (!r)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  r->scene = scene;
  r->db = db;
  r->width = width;
  r->height = height;
  r->threads = threads > 0 ? threads : satf_cpu_count();
  r->effects = scene->effects;
  satf_renderer_set_samples(r, scene->image.samples);
  take_view(r, scene);
  r->map_opt = satf_map_options_default();
  r->instanced = 1;
  r->incremental = 1;
  r->sparse_max = SATF_SPARSE_STRANDS_DEFAULT;
  r->lod_opt = lod_defaults();    /* r->lod 0: full detail unless asked */
  r->dom_eye_tol = INFINITY;      /* the shadows keep while the eye moves */
  r->dom_move_tol = DOM_MOVE_TOL; /* and while the hair moves little */
  st = satf_maps_create(db, &r->maps, err);
  if (st != SATF_OK) {
    free(r);
    return st;
  }
  r->w = satf_maps_width(r->maps);
  r->quads = 1;
  if (scene->material.model == SATF_MATERIAL_PHYSICAL && scene->effects.satf) {
    st = satf_maps_fiber_create(db, &scene->material, r->threads, &r->fiber,
                                err);
    r->quads = 2;
    if (st == SATF_OK && !(r->fgpu = calloc(1, sizeof *r->fgpu)))
      st = satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
    if (st == SATF_OK) {
      r->fgpu->with_global = 1;
      r->fgpu->threads = r->threads;
    }
  }
  if (st == SATF_OK)
    st = hierarchy_build(r, progress, progress_ctx, err);
  if (st == SATF_OK)
    st = resources_build(r, err);
  if (st == SATF_OK)
    st = sparse_build(r, err);
  if (st != SATF_OK) {
    satf_renderer_destroy(r);
    return st;
  }
  *out = r;
  return SATF_OK;
}

void satf_renderer_destroy(satf_renderer *r) {
  if (!r)
    return;
  strands_release(r);
  sparse_release(r);
  baseline_release(r);
  hierarchy_release(r);
  resources_release(r);
  frame_release(r);
  satf_maps_destroy(r->maps);
  satf_maps_fiber_destroy(r->fiber);
  if (r->fgpu)
    fiber_gpu_release(r->fgpu);
  free(r->fgpu);
  free(r->dom_points);
  free(r);
}

satf_status satf_renderer_resize(satf_renderer *r, int width, int height,
                                 satf_error *err) {
  satf_status st = check_size(width, height, err);
  if (st != SATF_OK)
    return st;
  if (width == r->width && height == r->height)
    return SATF_OK;
  r->width = width;
  r->height = height;
  return resources_alloc_screen(r, err);
}

void satf_renderer_stats(const satf_renderer *r, satf_render_stats *s) {
  *s = r->stats;
}
void satf_renderer_size(const satf_renderer *r, int *width, int *height) {
  *width = r->width;
  *height = r->height;
}
satf_scene_camera *satf_renderer_camera(satf_renderer *r) { return &r->camera; }
satf_scene_effects *satf_renderer_effects(satf_renderer *r) {
  return &r->effects;
}
satf_scene_light *satf_renderer_light(satf_renderer *r, int i) {
  return i >= 0 && i < r->nlights ? &r->lights[i] : NULL;
}
int satf_renderer_light_count(const satf_renderer *r) { return r->nlights; }
void satf_renderer_set_composite(satf_renderer *r, satf_composite mode) {
  r->composite = mode;
}
satf_composite satf_renderer_composite(const satf_renderer *r) {
  return r->composite;
}
void satf_renderer_set_lod(satf_renderer *r, int on) { r->lod = on != 0; }
int satf_renderer_lod(const satf_renderer *r) { return r->lod; }
void satf_renderer_set_shadow_move(satf_renderer *r, float texels) {
  r->dom_move_tol = texels >= 0.0f ? texels : -1.0f;
}
float satf_renderer_shadow_move(const satf_renderer *r) {
  return r->dom_move_tol;
}
unsigned satf_renderer_texture(const satf_renderer *r) {
  return satf_gl_target_color_texture(r->out, 0);
}
unsigned satf_renderer_framebuffer(const satf_renderer *r) {
  return satf_gl_target_fbo(r->out);
}

/* The composite pass of the renderer's mode; exact mode grows the
 * fragment arrays and draws again when a pixel had more fragments than
 * slots, and where a pixel has more than the arrays' largest size draws
 * once more keeping each pixel's nearest fragments (so the frame does not
 * depend on the order fragments arrive in). */
static satf_status composite(satf_renderer *r, satf_aov aov,
                             const float viewproj[16], long *count,
                             satf_error *err) {
  r->stats.overflow_pixels = 0;
  if (r->composite == SATF_COMPOSITE_ORDERED)
    return passes_ordered(r, aov, viewproj, err);
  long over = 0, ignore = 0;
  GLuint most = passes_lists(r, aov, viewproj, 0, count, &over);
  satf_status st = SATF_OK;
  if ((int)most > r->slots && r->slots < SATF_MAX_FRAGMENTS) {
    int slots = (int)most + 4;
    st = resources_alloc_lists(
        r, slots < SATF_MAX_FRAGMENTS ? slots : SATF_MAX_FRAGMENTS, err);
    if (st != SATF_OK)
      return st;
    most = passes_lists(r, aov, viewproj, 0, count, &over);
  }
  if (over > 0 && (st = resources_alloc_keys(r, err)) == SATF_OK)
    passes_lists(r, aov, viewproj, 1, count, &ignore);
  r->stats.overflow_pixels = over;
  return st;
}

/* A frame; with refresh 0 the maps and the deep opacity map of the
 * previous frame are reused (the AOV passes of one image). */
static satf_status render_sample(satf_renderer *r, satf_aov aov, int refresh,
                                 satf_frame_timing *timing, satf_error *err) {
  if (r->strands) /* the strand reference path (strands.c) */
    return strands_render_frame(r, aov, refresh, timing, err);
  if (!r->effects.satf) /* Fig. 4(a): paper 002, no database (baseline.c) */
    return baseline_frame(r, aov, refresh, timing, err);
  satf_frame_timing t;
  memset(&t, 0, sizeof t);
  double t0 = satf_now_seconds();
  satf_status st = refresh ? frame_update_maps(r, &t, err) : SATF_OK;
  if (st == SATF_OK)
    st = frame_instance_data(r, err);
  if (st != SATF_OK)
    return st;
  double t1 = satf_now_seconds();
  if (refresh && r->effects.cluster_shadows)
    passes_dom(r);
  glFinish();
  double t2 = satf_now_seconds();
  float viewproj[16];
  frame_camera(r, viewproj);
  long count = 0;
  st = composite(r, aov, viewproj, &count, err);
  if (st != SATF_OK)
    return st;
  glFinish();
  double t3 = satf_now_seconds();
  t.shadow_ms = 1e3 * (t2 - t1);
  t.lighting_ms = 1e3 * (t3 - t2);
  t.total_ms = 1e3 * (t3 - t0);
  t.fragments = (long)count;
  if (timing)
    *timing = t;
  return satf_gl_check("frame", err);
}

/* render_sample r->samples times with the camera jittered inside the pixel,
 * averaged (samples.c); the maps and shadows are made by the first. */
static satf_status render_frame(satf_renderer *r, satf_aov aov, int refresh,
                                satf_frame_timing *timing, satf_error *err) {
  int n = r->samples > 1 ? r->samples : 1;
  if (n == 1)
    return render_sample(r, aov, refresh, timing, err);
  satf_frame_timing sum, t;
  memset(&sum, 0, sizeof sum);
  satf_status st = SATF_OK;
  for (int i = 0; i < n && st == SATF_OK; i++) {
    samples_offset(i, n, r->jitter);
    st = render_sample(r, aov, refresh && i == 0, &t, err);
    if (st == SATF_OK)
      st = samples_add(r, i, n, err);
    if (i == 0) {
      sum = t;
      continue;
    }
    sum.shadow_ms += t.shadow_ms;
    sum.lighting_ms += t.lighting_ms;
    sum.total_ms += t.total_ms;
    sum.fragments += t.fragments;
  }
  r->jitter[0] = r->jitter[1] = 0.0f;
  if (st == SATF_OK)
    st = samples_finish(r, err);
  if (st == SATF_OK && timing)
    *timing = sum;
  return st;
}

satf_status satf_renderer_set_sparse_strands(satf_renderer *r, int max_strands,
                                             satf_error *err) {
  if (max_strands < 0 || max_strands > SATF_SPARSE_STRANDS_MAX)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "sparse strands: %d (0 to %d strands a cluster)",
                          max_strands, SATF_SPARSE_STRANDS_MAX);
  if (max_strands == r->sparse_max)
    return SATF_OK;
  r->sparse_max = max_strands;
  r->dom_valid = 0;                   /* other hair casts the shadows now */
  for (int i = 0; i < r->ninsts; i++) /* a cluster again needs its maps */
    frame_forget_lookups(&r->insts[i]);
  return sparse_build(r, err);
}
int satf_renderer_sparse_strands(const satf_renderer *r) {
  return r->sparse_max;
}

void satf_renderer_set_samples(satf_renderer *r, int samples) {
  r->samples = samples < 1                        ? 1
               : samples > SATF_SCENE_MAX_SAMPLES ? SATF_SCENE_MAX_SAMPLES
                                                  : samples;
}
int satf_renderer_samples(const satf_renderer *r) { return r->samples; }

satf_status satf_renderer_render(satf_renderer *r, satf_aov aov,
                                 satf_frame_timing *timing, satf_error *err) {
  return render_frame(r, aov, 1, timing, err);
}

void satf_renderer_present(satf_renderer *r) {
  glUseProgram(r->prog_display);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, satf_gl_target_color_texture(r->out, 0));
  glUniform1i(glGetUniformLocation(r->prog_display, "u_image"), 0);
  /* the target is premultiplied over transparent black */
  glUniform3fv(glGetUniformLocation(r->prog_display, "u_background"), 1,
               r->scene->background);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  passes_fullscreen(r);
}

satf_status satf_renderer_render_image(satf_renderer *r, int aovs,
                                       satf_image **out,
                                       satf_frame_timing *timing,
                                       satf_error *err) {
  *out = NULL;
  static const char *const names[] = {
      "R",         "G",         "B",        "A",        "diffuse.R",
      "diffuse.G", "diffuse.B", "specI.R",  "specI.G",  "specI.B",
      "specII.R",  "specII.G",  "specII.B", "shadow.Y", "alpha.Y"};
  int n = aovs ? 15 : 4;
  satf_image *img = NULL;
  satf_status st = satf_image_create(r->width, r->height, names, n, &img, err);
  if (st != SATF_OK)
    return st;
  size_t px = (size_t)r->width * (size_t)r->height;
  float *buf = malloc(px * 4 * sizeof(float));
  if (!buf) {
    satf_image_destroy(img);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  const char *const *dest[SATF_AOV_COUNT] = {
      (const char *const[]){"R", "G", "B", "A"},
      (const char *const[]){"diffuse.R", "diffuse.G", "diffuse.B", NULL},
      (const char *const[]){"specI.R", "specI.G", "specI.B", NULL},
      (const char *const[]){"specII.R", "specII.G", "specII.B", NULL},
      (const char *const[]){"shadow.Y", NULL, NULL, NULL},
      (const char *const[]){"alpha.Y", NULL, NULL, NULL}};
  int passes = aovs ? SATF_AOV_COUNT : 1;
  for (int a = 0; a < passes && st == SATF_OK; a++) {
    /* shadow and alpha AOVs are coverage-weighted: their composite over a
     * black background, as the other AOVs */
    st = render_frame(r, (satf_aov)a, a == 0, a == 0 ? timing : NULL, err);
    if (st == SATF_OK)
      st = satf_gl_target_read_bottom_up(r->out, 0, buf, px * 4, err);
    if (st == SATF_OK)
      st = satf_image_store_interleaved(img, buf, 4, dest[a],
                                        SATF_ROWS_BOTTOM_UP, err);
  }
  free(buf);
  if (st != SATF_OK) {
    satf_image_destroy(img);
    return st;
  }
  satf_image_set_background(img, r->scene->background);
  float view[16], proj[16], viewproj[16];
  frame_view_proj(r, view, proj);
  satf_mat4_mul(proj, view, viewproj);
  satf_image_set_camera(img, view, viewproj);
  *out = img;
  return SATF_OK;
}

satf_status satf_renderer_export_meshes(const satf_renderer *r,
                                        const char *path, int *written,
                                        satf_error *err) {
  *written = 0;
  const char *dot = strrchr(path, '.');
  if (!dot || (strcmp(dot, ".obj") && strcmp(dot, ".ply")))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: mesh files must end in .obj or .ply", path);
  for (int m = 0; m < r->nprotos; m++) {
    const proto *p = &r->protos[m];
    for (int k = 0; k < p->layers; k++) {
      char file[4096];
      int n = snprintf(file, sizeof file, "%.*s-m%d-l%d%s", (int)(dot - path),
                       path, m, k, dot);
      if (n < 0 || (size_t)n >= sizeof file)
        return satf_error_set(err, SATF_ERR_ARGUMENT, "%s: path too long",
                              path);
      satf_mesh *mesh = NULL;
      satf_status st = satf_cluster_build_layer_mesh(p->cluster, &p->geom.shell,
                                                     k, &mesh, err);
      if (st == SATF_OK)
        st = satf_mesh_write(mesh, file, err);
      satf_mesh_destroy(mesh);
      if (st != SATF_OK)
        return st;
      (*written)++;
    }
  }
  return SATF_OK;
}

satf_status satf_renderer_set_scene(satf_renderer *r, const satf_scene *scene,
                                    int *rebuilt, satf_error *err) {
  satf_status st = hierarchy_check(r, scene, err);
  if (st != SATF_OK)
    return st;
  int moved = 0;
  if (r->dom_move_tol < 0.0f) /* the hair may have moved (else passes_dom */
    r->dom_valid = 0;         /* measures how far) */
  st = hierarchy_update(r, scene, &moved, err);
  if (st == SATF_OK) /* the sparse clusters' strands move with them */
    st = sparse_build(r, err);
  take_view(r, scene);
  if (rebuilt)
    *rebuilt = moved;
  return st;
}
