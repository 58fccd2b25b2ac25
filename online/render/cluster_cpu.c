/* cluster_cpu.c - owns the clusters' per-frame CPU work (SATF Table 1: I,
 * C, M): the lights and eye in each instance's frame, the sector angles,
 * the database look-ups that fill every layer's maps and their upload, and
 * the instance data of the instanced draws. */
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
#error "the physical maps' words (map_fetch.glsl) assume a little-endian host"
#endif
#include "renderer_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "half.h"
#include "maps_gpu.h"
#include "mat4.h"
#include "satf/common.h"
#include "satf/math.h"

/* Whether instance `in` sees the eye and the key light where it saw them
 * (in its own frame) and its shells are unchanged since (no
 * cluster_cpu_forget_lookups): then its azimuths are last frame's. Otherwise
 * the new eye and light are kept for angles_job. */
static int inst_still(const satf_renderer *r, int lights_same, inst *in) {
  float eye[3], light[4];
  satf_mat4_point(in->inv, r->view.camera.position, eye);
  view_light_local(in->inv, &r->view.lights[0], light);
  /* the physical mode's maps follow every light, its colour too: still
   * only while none changed (lights_same) */
  if (r->incremental && (!r->fiber || lights_same) && !in->replaced &&
      !memcmp(eye, in->eye, sizeof eye) &&
      !memcmp(light, in->light, sizeof light))
    return 1;
  memcpy(in->eye, eye, sizeof eye);
  memcpy(in->light, light, sizeof light);
  return 0;
}

/* Sector azimuths of instance moved[i] towards the eye and the key light. */
typedef struct angle_jobs {
  satf_renderer *r;
  const int *moved;
} angle_jobs;

static int angles_job(void *ctx, size_t i, int thread) {
  (void)thread;
  const angle_jobs *j = ctx;
  satf_renderer *r = j->r;
  inst *in = &r->insts[j->moved[i]];
  in->replaced = 0;
  if (r->fiber) /* the physical maps find their own angles, every light's */
    return 0;
  satf_maps_angles(&in->geom, in->eye, in->light, in->angles);
  /* nothing to look up again: its layers need no job (build_maps) */
  in->still =
      r->incremental && !r->fiber &&
      !memcmp(in->angles, in->looked_up,
              2 * satf_shell_sector_count(&in->geom.shell) * sizeof(float));
  return 0;
}

/* Whether the scene's lights (all of them, their colours too) and the
 * TRT switch are those of the last frame's maps, remembered for the
 * next. */
static int lights_unchanged(satf_renderer *r) {
  size_t bytes = (size_t)r->view.nlights * sizeof(satf_scene_light);
  int same = r->fiber_nlights == r->view.nlights &&
             r->fiber_trt == r->effects.secondary_highlight &&
             !memcmp(r->fiber_lights, r->view.lights, bytes);
  memcpy(r->fiber_lights, r->view.lights, bytes);
  r->fiber_nlights = r->view.nlights;
  r->fiber_trt = r->effects.secondary_highlight;
  return same;
}

/* Every instance's azimuths; the check for a still instance runs here on
 * one thread: for a frame where little moved, threads would cost more to
 * start than the check itself. */
static satf_status update_angles(satf_renderer *r, satf_error *err) {
  int *moved = malloc((size_t)(r->ninsts > 0 ? r->ninsts : 1) * sizeof(int));
  if (!moved)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  size_t n = 0;
  int lights_same = lights_unchanged(r);
  for (int i = 0; i < r->ninsts; i++) {
    /* a sparse cluster is drawn as its strands (sparse.c): no maps */
    r->insts[i].still = r->protos[r->insts[i].proto].sparse ||
                        inst_still(r, lights_same, &r->insts[i]);
    if (!r->insts[i].still)
      moved[n++] = i;
  }
  angle_jobs aj = {r, moved};
  if (n > 0)
    satf_parallel_for(n, r->threads, angles_job, &aj, NULL, NULL);
  free(moved);
  return SATF_OK;
}

void cluster_cpu_forget_lookups(inst *in) {
  size_t n = 2 * satf_shell_sector_count(&in->geom.shell);
  for (size_t q = 0; q < n; q++)
    in->looked_up[q] = NAN;
  in->replaced = 1;
}

void cluster_cpu_forget_all_lookups(satf_renderer *r) {
  for (int i = 0; i < r->ninsts; i++)
    if (r->insts[i].looked_up)
      cluster_cpu_forget_lookups(&r->insts[i]);
}

/* One job per changed instance: its layers are built in floats in the
 * thread's scratch, summed for the s-maps and packed to halfs once
 * (half.h), so the maps kept and uploaded are half the bytes (the
 * physical maps are laid as halfs directly, with the thread's scratch
 * for their s-map sums). */
typedef struct inst_jobs {
  satf_renderer *r;
  int *inst_of;  /* per instance; job i builds part i % parts of instance */
  int parts;     /* inst_of[i / parts] (physical, maps_fiber.h; else 1) */
  long *lookups; /* per job */
} inst_jobs;

/* The physical mode's maps (maps_fiber.h): every light, in the
 * instance's frame, looked up every frame (the longitudinal angles and
 * every light change the maps, not only the key light's azimuths); laid
 * straight into the instance's halfs, with `sums` as scratch. */
static int fiber_maps(const satf_renderer *r, const inst *in, int part,
                      int parts, float *sums) {
  satf_fiber_light lights[SATF_SCENE_MAX_LIGHTS];
  maps_fiber_lights(&r->view, in->inv, lights);
  satf_map_options opt = r->map_opt;
  opt.orientation_free &= r->protos[in->proto].from_strands;
  opt.tilt = r->protos[in->proto].tilt;
  return satf_maps_fiber_build(r->maps, r->fiber, &in->geom, in->eye, lights,
                               r->view.nlights, r->effects.secondary_highlight,
                               &opt, part, parts, sums, in->texels);
}

/* Whether some sector of `in` keeps the azimuths of its last look-up: then
 * HSVs may keep their texels, which the float build must start from. */
static int some_sector_kept(const inst *in) {
  size_t n = satf_shell_sector_count(&in->geom.shell);
  for (size_t q = 0; q < n; q++)
    if (in->angles[2 * q] == in->looked_up[2 * q] &&
        in->angles[2 * q + 1] == in->looked_up[2 * q + 1])
      return 1;
  return 0;
}

/* Layer k of an instance in the paper's mode: only its HSVs whose sectors'
 * azimuths changed since their last look-up are looked up again (with
 * r->incremental; the rest keep their texels, which a look-up at the same
 * parameters would give again), and the azimuths looked up are
 * remembered. */
static int kk_layer(const satf_renderer *r, inst *in, int k, float *texels) {
  const satf_shell_params *sh = &in->geom.shell;
  satf_map_options opt = r->map_opt;
  opt.orientation_free &= r->protos[in->proto].from_strands;
  int lookups = satf_maps_update_layer(r->maps, &in->geom, in->angles,
                                       r->incremental ? in->looked_up : NULL,
                                       &opt, k, texels);
  /* sector (i, k, j) sits at ((i * layers + k) * su + j) (maps.c) */
  for (int row = 0; row <= sh->st; row++) {
    size_t q =
        2 * ((size_t)row * (size_t)sh->layers + (size_t)k) * (size_t)sh->su;
    memcpy(in->looked_up + q, in->angles + q,
           2 * (size_t)sh->su * sizeof(float));
  }
  return lookups;
}

/* Floats of an instance's maps (every texture layer). */
static size_t inst_floats(const satf_renderer *r, const inst *in) {
  return satf_maps_layer_texels(&in->geom, r->w) * 4 *
         (size_t)in->geom.shell.layers * (size_t)r->quads;
}

static int inst_job(void *ctx, size_t i, int thread) {
  inst_jobs *j = ctx;
  satf_renderer *r = j->r;
  inst *in = &r->insts[j->inst_of[i / (size_t)j->parts]];
  float *f = r->scratch[thread];
  size_t n = inst_floats(r, in);
  size_t layer = satf_maps_layer_texels(&in->geom, r->w) * 4;
  long lookups = 0;
  if (r->fiber) { /* every layer whole, every time (build_maps uploads) */
    lookups = fiber_maps(r, in, (int)(i % (size_t)j->parts), j->parts, f);
  } else {
    /* half -> float -> half is exact: kept texels come back unchanged */
    if (r->incremental && some_sector_kept(in))
      half_unpack(in->texels, f, n);
    for (int k = 0; k < in->geom.shell.layers; k++)
      lookups += kk_layer(r, in, k, f + (size_t)k * layer);
    if (lookups > 0) {
      satf_maps_shadow_sums(&in->geom, r->w, f);
      half_pack(f, in->texels, n);
      in->stale_upload = 1;
    }
  }
  j->lookups[i] = lookups;
  return 0;
}

/* at most this many instances are split by layers (an array on the
 * stack; more threads than this split nothing) */
#define LAYER_SPLIT_MAX 64

/* Fewer changed instances than threads (the single-cluster scenes of
 * Fig. 6): one instance per job would leave threads idle, so each
 * instance's layers are spread over them (its layers' look-ups are
 * independent, kk_layer), each instance in a scratch buffer of its own,
 * and the s-map sums and packing follow per instance. Job i is layer
 * i % layers of instance i / layers; the paper's mode only. */
typedef struct layer_jobs {
  satf_renderer *r;
  const int *inst_of;
  const int *unpack; /* per instance: start from its kept texels */
  int layers;        /* the most layers of any of them */
  long *lookups;     /* per job */
} layer_jobs;

static int layer_job(void *ctx, size_t i, int thread) {
  (void)thread;
  layer_jobs *j = ctx;
  size_t q = i / (size_t)j->layers;
  int k = (int)(i % (size_t)j->layers);
  inst *in = &j->r->insts[j->inst_of[q]];
  j->lookups[i] = 0;
  if (k >= in->geom.shell.layers)
    return 0;
  size_t layer = satf_maps_layer_texels(&in->geom, j->r->w) * 4;
  float *f = j->r->scratch[q] + (size_t)k * layer;
  /* half -> float -> half is exact: kept texels come back unchanged */
  if (j->unpack[q])
    half_unpack(in->texels + (size_t)k * layer, f, layer);
  j->lookups[i] = kk_layer(j->r, in, k, f);
  return 0;
}

static int sums_job(void *ctx, size_t q, int thread) {
  (void)thread;
  layer_jobs *j = ctx;
  inst *in = &j->r->insts[j->inst_of[q]];
  long lookups = 0;
  for (int k = 0; k < in->geom.shell.layers; k++)
    lookups += j->lookups[q * (size_t)j->layers + (size_t)k];
  if (lookups > 0) {
    float *f = j->r->scratch[q];
    satf_maps_shadow_sums(&in->geom, j->r->w, f);
    half_pack(f, in->texels, inst_floats(j->r, in));
    in->stale_upload = 1;
  }
  return 0;
}

/* build_maps for jobs (< r->threads, so each has a scratch buffer)
 * instances by layers; the look-ups counted into *lookups. */
static satf_status build_maps_by_layer(satf_renderer *r, const int *inst_of,
                                       size_t jobs, long *lookups,
                                       satf_error *err) {
  int layers = 1, unpack[LAYER_SPLIT_MAX];
  for (size_t q = 0; q < jobs; q++) {
    const inst *in = &r->insts[inst_of[q]];
    layers = in->geom.shell.layers > layers ? in->geom.shell.layers : layers;
    unpack[q] = r->incremental && some_sector_kept(in);
  }
  size_t n = jobs * (size_t)layers;
  layer_jobs lj = {r, inst_of, unpack, layers, calloc(n, sizeof(long))};
  if (!lj.lookups)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  satf_parallel_for(n, r->threads, layer_job, &lj, NULL, NULL);
  satf_parallel_for(jobs, r->threads, sums_job, &lj, NULL, NULL);
  for (size_t i = 0; i < n; i++)
    *lookups += lj.lookups[i];
  free(lj.lookups);
  return SATF_OK;
}

/* r->scratch: one buffer per map thread, each of the largest instance's
 * floats (physical: its s-map sums); kept between frames (a fresh one would
 * fault its pages in every frame). */
static satf_status grow_scratch(satf_renderer *r, size_t floats,
                                satf_error *err) {
  if (r->scratch_n >= r->threads && r->scratch_floats >= floats)
    return SATF_OK;
  cluster_cpu_release(r);
  int n = r->threads > 0 ? r->threads : 1;
  r->scratch = calloc((size_t)n, sizeof *r->scratch);
  for (int t = 0; r->scratch && t < n; t++)
    if (!(r->scratch[t] = malloc((floats > 0 ? floats : 1) * sizeof(float))))
      break;
  if (!r->scratch || !r->scratch[n - 1]) {
    cluster_cpu_release(r);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot allocate %zu map floats per thread", floats);
  }
  r->scratch_n = n;
  r->scratch_floats = floats;
  return SATF_OK;
}

void cluster_cpu_release(satf_renderer *r) {
  for (int t = 0; r->scratch && t < r->scratch_n; t++)
    free(r->scratch[t]);
  free(r->scratch);
  r->scratch = NULL;
  r->scratch_n = 0;
  r->scratch_floats = 0;
}

/* Every layer map and s-map of every instance that changed; *lookups
 * counts the database look-ups. */
static satf_status build_maps(satf_renderer *r, long *lookups,
                              satf_error *err) {
  size_t jobs = 0, most = 0;
  for (int i = 0; i < r->ninsts; i++)
    if (!r->insts[i].still) {
      jobs++;
      size_t n = r->fiber
                     ? satf_maps_fiber_scratch_floats(&r->insts[i].geom, r->w)
                     : inst_floats(r, &r->insts[i]);
      most = n > most ? n : most;
    }
  *lookups = 0;
  if (jobs == 0)
    return SATF_OK;
  satf_status st = grow_scratch(r, most, err);
  if (st != SATF_OK)
    return st;
  /* fewer changed instances than threads (one cluster): the physical
   * maps' instances in parts, so every thread has work */
  int parts = r->fiber && jobs < (size_t)r->threads
                  ? (int)(((size_t)r->threads + jobs - 1) / jobs)
                  : 1;
  inst_jobs ij = {r, malloc(jobs * sizeof(int)), parts,
                  calloc(jobs * (size_t)parts, sizeof(long))};
  if (!ij.inst_of || !ij.lookups) {
    free(ij.inst_of);
    free(ij.lookups);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  size_t q = 0;
  for (int i = 0; i < r->ninsts; i++)
    if (!r->insts[i].still)
      ij.inst_of[q++] = i;
  if (!r->fiber && (int)jobs < r->threads && jobs <= LAYER_SPLIT_MAX) {
    st = build_maps_by_layer(r, ij.inst_of, jobs, lookups, err);
    free(ij.inst_of);
    free(ij.lookups);
    return st;
  }
  satf_parallel_for(jobs * (size_t)parts, r->threads, inst_job, &ij, NULL,
                    NULL);
  for (q = 0; q < jobs * (size_t)parts; q++) {
    *lookups += ij.lookups[q];
    if (r->fiber && ij.lookups[q] > 0)
      r->insts[ij.inst_of[q / (size_t)parts]].stale_upload = 1;
  }
  free(ij.inst_of);
  free(ij.lookups);
  return SATF_OK;
}

/* The maps built on the GPU (maps_gpu.h), the paper's or the physical
 * mode's: the instances whose eye or key light moved in their frame (any
 * light in the physical mode; inst_still: the same test as the CPU's,
 * without its azimuths, which the GPU finds) are built whole; I is
 * that test, C the GPU's pass (to its end), M the CPU's uploads of eyes
 * and lights (and of geometry where it changed). t->lookups counts the
 * HSVs built, at least one look-up each. */
static satf_status gpu_update_maps(satf_renderer *r, satf_frame_timing *t,
                                   satf_error *err) {
  double t0 = satf_now_seconds();
  int *moved = malloc((size_t)(r->ninsts > 0 ? r->ninsts : 1) * sizeof(int));
  if (!moved)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  int n = 0, lights_same = lights_unchanged(r);
  t->lookups = 0;
  for (int i = 0; i < r->ninsts; i++) {
    inst *in = &r->insts[i];
    in->still = r->protos[in->proto].sparse || inst_still(r, lights_same, in);
    if (!in->still) {
      in->replaced = 0;
      moved[n++] = i;
      t->lookups += (long)satf_shell_hsv_count(&in->geom.shell);
    }
  }
  double t1 = satf_now_seconds(), up = 0.0;
  satf_status st =
      n > 0 ? maps_gpu_build(r, r->mgpu, moved, n, &up, err) : SATF_OK;
  free(moved);
  r->maps_changed = n;
  if (n > 0) /* the deep opacity map reads their alpha */
    r->dom.maps_stale = r->fill_dom.maps_stale = 1;
  glFinish();
  double t2 = satf_now_seconds();
  t->index_ms = 1e3 * (t1 - t0);
  t->upload_ms = up;
  t->maps_ms = 1e3 * (t2 - t1) - up;
  return st;
}

/* Auto's choice of the GPU's maps failed with err: the CPU's from now on
 * (satf_renderer_set_maps), the reason kept in maps_note, err cleared. */
static void fall_back_to_cpu(satf_renderer *r, satf_error *err) {
  snprintf(r->maps_note, sizeof r->maps_note, "%s",
           err && err->message[0] ? err->message : "the GPU's maps failed");
  satf_error_clear(err);
  maps_gpu_destroy(r->mgpu);
  r->mgpu = NULL;
  cluster_cpu_forget_all_lookups(r);
  r->maps_mode = SATF_MAPS_CPU;
}

satf_status cluster_cpu_update_maps(satf_renderer *r, satf_frame_timing *t,
                                    satf_error *err) {
  if (r->maps_mode == SATF_MAPS_GPU) {
    satf_status st = r->mgpu ? SATF_OK : maps_gpu_create(r, &r->mgpu, err);
    if (st == SATF_OK)
      st = gpu_update_maps(r, t, err);
    if (st == SATF_OK || !r->maps_auto)
      return st;
    /* auto's choice: the CPU's maps serve on any context, this frame too */
    fall_back_to_cpu(r, err);
    memset(t, 0, sizeof *t);
  }
  double t0 = satf_now_seconds();
  satf_status st = update_angles(r, err);
  if (st != SATF_OK)
    return st;
  double t1 = satf_now_seconds();
  st = build_maps(r, &t->lookups, err);
  if (st != SATF_OK)
    return st;
  double t2 = satf_now_seconds();
  r->maps_changed = 0;
  for (int i = 0; i < r->ninsts; i++) {
    inst *in = &r->insts[i];
    if (!in->stale_upload)
      continue;
    const satf_shell_params *sh = &in->geom.shell;
    glBindTexture(GL_TEXTURE_2D_ARRAY, in->tex);
    /* a physical texel's 8 halfs are 4 words, low half first on this
     * little-endian host, as the shader unpacks them (map_fetch.glsl) */
    glTexSubImage3D(
        GL_TEXTURE_2D_ARRAY, 0, 0, 0, in->layer0, sh->su * r->w, 2 * sh->st,
        sh->layers, r->quads == 2 ? GL_RGBA_INTEGER : GL_RGBA,
        r->quads == 2 ? GL_UNSIGNED_INT : GL_HALF_FLOAT, in->texels);
    in->stale_upload = 0;
    r->maps_changed++;
  }
  if (r->maps_changed) /* the deep opacity map reads their alpha */
    r->dom.maps_stale = r->fill_dom.maps_stale = 1;
  glFinish();
  double t3 = satf_now_seconds();
  t->index_ms = 1e3 * (t1 - t0);
  t->maps_ms = 1e3 * (t2 - t1);
  t->upload_ms = 1e3 * (t3 - t2);
  return satf_gl_check("map upload", err);
}

satf_status cluster_cpu_instance_data(satf_renderer *r, satf_error *err) {
  size_t n = (size_t)(r->ninsts > 0 ? r->ninsts : 1);
  float *models = calloc(n * 16, sizeof(float));
  float *views = calloc(n * CLUSTER_VIEW_FLOATS, sizeof(float));
  if (!models || !views) {
    free(models);
    free(views);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  lod_update(r);
  for (int i = 0; i < r->ninsts; i++) {
    const inst *in = &r->insts[i];
    /* GLSL's mat4 is column-major; in->m is row-major */
    for (int a = 0; a < 4; a++)
      for (int b = 0; b < 4; b++)
        models[16 * (size_t)i + 4 * (size_t)b + (size_t)a] = in->m[4 * a + b];
    float *v = views + CLUSTER_VIEW_FLOATS * (size_t)i;
    satf_mat4_point(in->inv, r->view.camera.position, v);
    v[3] = in->lod; /* the eye's w: the level (glsl/shade_fs.glsl) */
    for (int k = 0; k < r->view.nlights; k++)
      view_light_local(in->inv, &r->view.lights[k], v + 4 + 4 * k);
  }
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->inst_models);
  glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0,
                  (GLsizeiptr)(n * 16 * sizeof(float)), models);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->inst_shading);
  glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0,
                  (GLsizeiptr)(n * CLUSTER_VIEW_FLOATS * sizeof(float)), views);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  free(models);
  free(views);
  return satf_gl_check("instance data", err);
}
