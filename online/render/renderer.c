/* renderer.c - owns the renderer's public API (satf/render.h): creating
 * and destroying it, switching scenes and image sizes, its interactive
 * state, and rendering frames and images: it chooses the frame's drawing
 * path (path.h) and runs it once per anti-aliasing sample (samples.c). */
#include "renderer_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "maps_gpu.h"
#include "mat4.h"
#include "path.h"
#include "satf/common.h"
#include "shaders.h"

const char *satf_aov_name(satf_aov aov) {
  static const char *names[] = {"beauty", "diffuse", "specI", "specII",
                                "shadow", "alpha",   "depth"};
  return aov < SATF_AOV_COUNT ? names[aov] : "unknown";
}

static satf_status check_size(int width, int height, satf_error *err) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "image size %dx%d", width,
                          height);
  return SATF_OK;
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
  r->pixel_filter = SATF_PIXEL_FILTER_AUTO;
  r->view.width = width;
  r->view.height = height;
  r->threads = threads > 0 ? threads : satf_cpu_count();
  r->effects = scene->effects;
  satf_renderer_set_samples(r, scene->image.samples);
  view_take(&r->view, scene);
  r->map_opt = satf_map_options_default();
  r->instanced = 1;
  r->incremental = 1;
  r->sparse_max = SATF_SPARSE_STRANDS_DEFAULT;
  r->lod_opt = lod_defaults();    /* r->lod 0: full detail unless asked */
  r->dom.eye_tol = INFINITY;      /* the shadows keep while the eye moves */
  r->dom.move_tol = DOM_MOVE_TOL; /* and while the hair moves little */
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
  if (st == SATF_OK) /* the GPU's maps on a hardware GPU */
    st = satf_renderer_set_maps(r, SATF_MAPS_DEFAULT, err);
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
  /* every path's own state (the clusters' first: their sparse strands
   * mark the prototypes), then what they all read */
  clusters_path.destroy(r);
  strands_path.destroy(r);
  baseline_path.destroy(r);
  hierarchy_release(r);
  resources_release(r);
  samples_release(&r->accum);
  dom_release(&r->dom);
  dom_release(&r->fill_dom);
  maps_gpu_destroy(r->mgpu);
  satf_maps_destroy(r->maps);
  satf_maps_fiber_destroy(r->fiber);
  if (r->fgpu)
    fiber_gpu_release(r->fgpu);
  free(r->fgpu);
  free(r);
}

satf_status satf_renderer_resize(satf_renderer *r, int width, int height,
                                 satf_error *err) {
  satf_status st = check_size(width, height, err);
  if (st != SATF_OK)
    return st;
  if (width == r->view.width && height == r->view.height)
    return SATF_OK;
  r->view.width = width;
  r->view.height = height;
  return resources_alloc_screen(r, err);
}

void satf_renderer_stats(const satf_renderer *r, satf_render_stats *s) {
  *s = r->stats;
}
void satf_renderer_size(const satf_renderer *r, int *width, int *height) {
  *width = r->view.width;
  *height = r->view.height;
}
satf_scene_camera *satf_renderer_camera(satf_renderer *r) {
  return &r->view.camera;
}
satf_scene_effects *satf_renderer_effects(satf_renderer *r) {
  return &r->effects;
}
satf_scene_light *satf_renderer_light(satf_renderer *r, int i) {
  return i >= 0 && i < r->view.nlights ? &r->view.lights[i] : NULL;
}
int satf_renderer_light_count(const satf_renderer *r) {
  return r->view.nlights;
}
void satf_renderer_set_composite(satf_renderer *r, satf_composite mode) {
  r->composite = mode;
}
satf_composite satf_renderer_composite(const satf_renderer *r) {
  return r->composite;
}
void satf_renderer_set_pixel_filter(satf_renderer *r, satf_pixel_filter f) {
  r->pixel_filter =
      f == SATF_PIXEL_FILTER_BLACKMAN_HARRIS || f == SATF_PIXEL_FILTER_AUTO
          ? f
          : SATF_PIXEL_FILTER_BOX;
}
satf_pixel_filter satf_renderer_pixel_filter(const satf_renderer *r) {
  return r->pixel_filter;
}
void satf_renderer_set_lod(satf_renderer *r, int on) { r->lod = on != 0; }
int satf_renderer_lod(const satf_renderer *r) { return r->lod; }
void satf_renderer_set_pass_timing(satf_renderer *r, int on) {
  r->pass_timing = on != 0;
}
int satf_renderer_pass_timing(const satf_renderer *r) { return r->pass_timing; }
void satf_renderer_set_shadow_move(satf_renderer *r, float texels) {
  r->dom.move_tol = texels >= 0.0f ? texels : -1.0f;
}
float satf_renderer_shadow_move(const satf_renderer *r) {
  return r->dom.move_tol;
}
/* SATF_MAPS_AUTO: the GPU's maps on a hardware GPU, where the compute
 * pass is the cheaper (an H200: 0.1-10 ms a frame against 7-107 for the
 * CPU's look-ups and upload), the CPU's on a software rasteriser, where
 * it is 3-10 times the dearer (satf/render.h) */
static satf_maps_mode maps_resolve(const char *gl_renderer) {
  return satf_gl_renderer_is_software(gl_renderer) ? SATF_MAPS_CPU
                                                   : SATF_MAPS_GPU;
}

/* The mode `mode` from now on; the other mode's maps are not these. */
static void switch_maps(satf_renderer *r, satf_maps_mode mode) {
  if (mode != r->maps_mode)
    cluster_cpu_forget_all_lookups(r);
  r->maps_mode = mode;
}

void renderer_maps_auto_as(satf_renderer *r, satf_maps_mode mode) {
  switch_maps(r, mode);
  r->maps_auto = 1;
  r->maps_note[0] = '\0';
}

satf_status satf_renderer_set_maps(satf_renderer *r, satf_maps_mode mode,
                                   satf_error *err) {
  if (mode != SATF_MAPS_CPU && mode != SATF_MAPS_GPU && mode != SATF_MAPS_AUTO)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "maps mode %d", (int)mode);
  if (mode == SATF_MAPS_AUTO) {
    /* the GPU's maps made at the first frame that builds maps
     * (cluster_cpu_update_maps): the strand and baseline paths, and
     * scenes of single strands, never need them */
    renderer_maps_auto_as(r,
                          maps_resolve((const char *)glGetString(GL_RENDERER)));
    return SATF_OK;
  }
  if (mode == SATF_MAPS_GPU && !r->mgpu) {
    satf_status st = maps_gpu_create(r, &r->mgpu, err);
    if (st != SATF_OK)
      return st;
  }
  switch_maps(r, mode);
  r->maps_auto = 0;
  r->maps_note[0] = '\0';
  return SATF_OK;
}
const char *satf_renderer_maps_note(const satf_renderer *r) {
  return r->maps_note;
}
satf_maps_mode satf_renderer_maps(const satf_renderer *r) {
  return r->maps_mode;
}
const char *satf_maps_mode_name(satf_maps_mode mode) {
  return mode == SATF_MAPS_GPU    ? "gpu"
         : mode == SATF_MAPS_AUTO ? "auto"
                                  : "cpu";
}
int satf_maps_mode_parse(const char *name, satf_maps_mode *mode) {
  static const satf_maps_mode modes[] = {SATF_MAPS_CPU, SATF_MAPS_GPU,
                                         SATF_MAPS_AUTO};
  for (size_t i = 0; i < sizeof modes / sizeof modes[0]; i++)
    if (!strcmp(name, satf_maps_mode_name(modes[i]))) {
      *mode = modes[i];
      return 0;
    }
  return -1;
}
unsigned satf_renderer_texture(const satf_renderer *r) {
  return satf_gl_target_color_texture(r->out, 0);
}
unsigned satf_renderer_framebuffer(const satf_renderer *r) {
  return satf_gl_target_fbo(r->out);
}

/* The frame's drawing path: the strands when the caller gave some
 * (satf_renderer_set_strands), else Fig. 4(a)'s baseline when SATF is
 * switched off, else the clusters; a path chosen for the first time
 * builds its state. */
static satf_status choose_path(satf_renderer *r, satf_error *err) {
  const render_path *p = r->strands         ? &strands_path
                         : !r->effects.satf ? &baseline_path
                                            : &clusters_path;
  if (p == r->path)
    return SATF_OK;
  satf_status st = p->create ? p->create(r, err) : SATF_OK;
  if (st == SATF_OK)
    r->path = p;
  return st;
}

/* The frame's path run r->samples times with the camera jittered inside
 * the pixel, averaged (samples.c); the maps and shadows are made by the
 * first. */
static satf_status render_frame(satf_renderer *r, satf_aov aov, int refresh,
                                satf_frame_timing *timing, satf_error *err) {
  satf_status st = choose_path(r, err);
  if (st != SATF_OK)
    return st;
  int n = r->samples > 1 ? r->samples : 1;
  if (n == 1)
    return r->path->frame(r, aov, refresh, timing, err);
  satf_frame_timing sum, t;
  memset(&sum, 0, sizeof sum);
  for (int i = 0; i < n && st == SATF_OK; i++) {
    samples_offset(i, n, r->view.jitter);
    st = r->path->frame(r, aov, refresh && i == 0, &t, err);
    if (st == SATF_OK)
      st = samples_add(&r->accum, r->out, r->empty_vao, i, n, err);
    if (i == 0) {
      sum = t;
      continue;
    }
    sum.shadow_ms += t.shadow_ms;
    sum.lighting_ms += t.lighting_ms;
    sum.total_ms += t.total_ms;
    sum.fragments += t.fragments;
    sum.shells_ms += t.shells_ms;
    sum.strands_ms += t.strands_ms;
    sum.resolve_ms += t.resolve_ms;
  }
  r->view.jitter[0] = r->view.jitter[1] = 0.0f;
  if (st == SATF_OK)
    st = samples_finish(&r->accum, r->out, r->empty_vao, err);
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
  r->dom.valid = r->fill_dom.valid = 0; /* other hair casts the shadows */
  cluster_cpu_forget_all_lookups(r);    /* a cluster again needs its maps */
  satf_status st = sparse_build(r, err);
  /* clusters drawn as strands until now get their features and maps */
  return st == SATF_OK ? hierarchy_prepare(r, err) : st;
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
  shaders_fullscreen(r->empty_vao);
}

/* Blender's and Nuke's depth where nothing was hit (Cycles' film writes
 * 1e10 for an empty depth pass) */
#define NO_DEPTH 1e10f

/* Sorts n (at most SATF_SCENE_MAX_SAMPLES) values; returns the lower
 * middle one. */
static float median(float *v, int n) {
  for (int a = 1; a < n; a++) {
    float x = v[a];
    int b = a - 1;
    for (; b >= 0 && v[b] > x; b--)
      v[b + 1] = v[b];
    v[b + 1] = x;
  }
  return v[(n - 1) / 2];
}

/* SATF_AOV_DEPTH into the image's Z, rows bottom up in buf (4 floats a
 * pixel): each sample decoded (the half and its remainder added,
 * glsl/depth_encode.glsl; NO_DEPTH where alpha is 0), and of several
 * samples the median, the lower one for an even count: the depth most of
 * the pixel's samples see (half coverage again, as within one sample,
 * glsl/resolve_fs.glsl), never a mean across an edge, which lies where
 * nothing is. */
static satf_status render_depth(satf_renderer *r, float *buf, satf_image *img,
                                satf_error *err) {
  int n = r->samples > 1 ? r->samples : 1;
  size_t px = (size_t)r->view.width * (size_t)r->view.height;
  float *z = malloc(px * (size_t)n * sizeof(float));
  if (!z)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  satf_status st = SATF_OK;
  for (int i = 0; i < n && st == SATF_OK; i++) {
    if (n > 1)
      samples_offset(i, n, r->view.jitter);
    st = r->path->frame(r, SATF_AOV_DEPTH, 0, NULL, err);
    if (st == SATF_OK)
      st = satf_gl_target_read_bottom_up(r->out, 0, buf, px * 4, err);
    for (size_t p = 0; st == SATF_OK && p < px; p++)
      z[p * (size_t)n + (size_t)i] =
          buf[4 * p + 3] > 0.0f ? buf[4 * p] + buf[4 * p + 1] : NO_DEPTH;
  }
  r->view.jitter[0] = r->view.jitter[1] = 0.0f;
  /* z[p] lies in pixel p / n's samples, already taken */
  for (size_t p = 0; st == SATF_OK && p < px; p++)
    z[p] = median(z + p * (size_t)n, n);
  static const char *const name[1] = {"Z"};
  if (st == SATF_OK)
    st =
        satf_image_store_interleaved(img, z, 1, name, SATF_ROWS_BOTTOM_UP, err);
  free(z);
  return st;
}

satf_status satf_renderer_render_image(satf_renderer *r, int aovs,
                                       satf_image **out,
                                       satf_frame_timing *timing,
                                       satf_error *err) {
  *out = NULL;
  static const char *const names[] = {
      "R",         "G",        "B",       "A",       "diffuse.R", "diffuse.G",
      "diffuse.B", "specI.R",  "specI.G", "specI.B", "specII.R",  "specII.G",
      "specII.B",  "shadow.Y", "alpha.Y", "Z"};
  int n = aovs ? 16 : 4;
  satf_image *img = NULL;
  satf_status st =
      satf_image_create(r->view.width, r->view.height, names, n, &img, err);
  if (st != SATF_OK)
    return st;
  size_t px = (size_t)r->view.width * (size_t)r->view.height;
  float *buf = malloc(px * 4 * sizeof(float));
  if (!buf) {
    satf_image_destroy(img);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  const char *const *dest[SATF_AOV_DEPTH] = {
      (const char *const[]){"R", "G", "B", "A"},
      (const char *const[]){"diffuse.R", "diffuse.G", "diffuse.B", NULL},
      (const char *const[]){"specI.R", "specI.G", "specI.B", NULL},
      (const char *const[]){"specII.R", "specII.G", "specII.B", NULL},
      (const char *const[]){"shadow.Y", NULL, NULL, NULL},
      (const char *const[]){"alpha.Y", NULL, NULL, NULL}};
  int passes = aovs ? SATF_AOV_DEPTH : 1; /* then the depth */
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
  if (st == SATF_OK && aovs)
    st = render_depth(r, buf, img, err);
  free(buf);
  if (st != SATF_OK) {
    satf_image_destroy(img);
    return st;
  }
  satf_image_set_background(img, r->scene->background);
  /* the camera as a compositor reads it (worldToCamera, worldToNDC) */
  float look[16], proj[16], viewproj[16];
  view_matrices(&r->view, look, proj);
  satf_mat4_mul(proj, look, viewproj);
  satf_image_set_camera(img, look, viewproj);
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
  /* the hair may have moved (else cluster_dom_update measures how far;
   * the strand path's maps are drawn again: draw_dom_lights) */
  if (r->dom.move_tol < 0.0f || r->strands)
    r->dom.valid = r->fill_dom.valid = 0;
  st = hierarchy_update(r, scene, &moved, err);
  if (st == SATF_OK) /* the sparse clusters' strands move with them */
    st = sparse_build(r, err);
  view_take(&r->view, scene);
  if (rebuilt)
    *rebuilt = moved;
  return st;
}
