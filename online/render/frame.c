/* frame.c - owns the renderer's per-frame CPU work (SATF Table 1: I, C,
 * M): the lights and eye in each instance's frame, the sector angles, the
 * database look-ups that fill every layer's maps and their upload, and the
 * frame's transforms (camera, key light, screen box, depth order). */
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
#error "the physical maps' words (map_fetch.glsl) assume a little-endian host"
#endif
#include "renderer_internal.h"

#include <stdlib.h>
#include <string.h>

#include "half.h"
#include "mat4.h"
#include "satf/common.h"
#include "satf/math.h"

void frame_light_vector(const satf_scene_light *l, float out[4]) {
  if (l->type == SATF_SCENE_LIGHT_POINT) {
    memcpy(out, l->position, 3 * sizeof(float));
    out[3] = 1.0f;
  } else {
    out[0] = -l->direction[0];
    out[1] = -l->direction[1];
    out[2] = -l->direction[2];
    out[3] = 0.0f;
  }
}

void frame_light_local(const float inv[16], const satf_scene_light *l,
                       float out[4]) {
  float lv[4];
  frame_light_vector(l, lv);
  if (lv[3] != 0.0f)
    satf_mat4_point(inv, lv, out);
  else
    satf_mat4_vector(inv, lv, out);
  out[3] = lv[3];
}

void frame_light_colors(const satf_renderer *r, float *col) {
  for (int k = 0; k < r->nlights; k++)
    for (int a = 0; a < 3; a++)
      col[3 * k + a] = r->lights[k].color[a] * r->lights[k].intensity;
}

/* Whether instance `in` sees the eye and the key light where it saw them
 * (in its own frame) and its shells are unchanged since (no
 * frame_forget_lookups): then its azimuths are last frame's. Otherwise
 * the new eye and light are kept for angles_job. */
static int inst_still(const satf_renderer *r, int lights_same, inst *in) {
  float eye[3], light[4];
  satf_mat4_point(in->inv, r->camera.position, eye);
  frame_light_local(in->inv, &r->lights[0], light);
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

/* Every instance's azimuths; the check for a still instance runs here on
 * one thread: for a frame where little moved, threads would cost more to
 * start than the check itself. */
static satf_status update_angles(satf_renderer *r, satf_error *err) {
  int *moved = malloc((size_t)(r->ninsts > 0 ? r->ninsts : 1) * sizeof(int));
  if (!moved)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  size_t n = 0;
  size_t bytes = (size_t)r->nlights * sizeof(satf_scene_light);
  int lights_same = r->fiber_nlights == r->nlights &&
                    r->fiber_trt == r->effects.secondary_highlight &&
                    !memcmp(r->fiber_lights, r->lights, bytes);
  memcpy(r->fiber_lights, r->lights, bytes);
  r->fiber_nlights = r->nlights;
  r->fiber_trt = r->effects.secondary_highlight;
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

void frame_forget_lookups(inst *in) {
  size_t n = 2 * satf_shell_sector_count(&in->geom.shell);
  for (size_t q = 0; q < n; q++)
    in->looked_up[q] = NAN;
  in->replaced = 1;
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
  float col[3 * SATF_SCENE_MAX_LIGHTS];
  frame_light_colors(r, col);
  for (int l = 0; l < r->nlights; l++) {
    frame_light_local(in->inv, &r->lights[l], lights[l].local);
    memcpy(lights[l].rgb, col + 3 * l, sizeof lights[l].rgb);
  }
  return satf_maps_fiber_build(r->maps, r->fiber, &in->geom, in->eye, lights,
                               r->nlights, r->effects.secondary_highlight,
                               &r->map_opt, part, parts, sums, in->texels);
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
  int lookups = satf_maps_update_layer(r->maps, &in->geom, in->angles,
                                       r->incremental ? in->looked_up : NULL,
                                       &r->map_opt, k, texels);
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
  frame_release(r);
  int n = r->threads > 0 ? r->threads : 1;
  r->scratch = calloc((size_t)n, sizeof *r->scratch);
  for (int t = 0; r->scratch && t < n; t++)
    if (!(r->scratch[t] = malloc((floats > 0 ? floats : 1) * sizeof(float))))
      break;
  if (!r->scratch || !r->scratch[n - 1]) {
    frame_release(r);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot allocate %zu map floats per thread", floats);
  }
  r->scratch_n = n;
  r->scratch_floats = floats;
  return SATF_OK;
}

void frame_release(satf_renderer *r) {
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

satf_status frame_update_maps(satf_renderer *r, satf_frame_timing *t,
                              satf_error *err) {
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
    r->dom_maps_stale = 1;
  glFinish();
  double t3 = satf_now_seconds();
  t->index_ms = 1e3 * (t1 - t0);
  t->maps_ms = 1e3 * (t2 - t1);
  t->upload_ms = 1e3 * (t3 - t2);
  return satf_gl_check("map upload", err);
}

/* std430 layout of glsl/shade_fs.glsl's per-instance view: the eye (xyz,
 * w the level of detail) and SATF_SCENE_MAX_LIGHTS lights, 4 floats each. */
#define VIEW_FLOATS (4 + 4 * SATF_SCENE_MAX_LIGHTS)

satf_status frame_instance_data(satf_renderer *r, satf_error *err) {
  size_t n = (size_t)(r->ninsts > 0 ? r->ninsts : 1);
  float *models = calloc(n * 16, sizeof(float));
  float *views = calloc(n * VIEW_FLOATS, sizeof(float));
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
    float *v = views + VIEW_FLOATS * (size_t)i;
    satf_mat4_point(in->inv, r->camera.position, v);
    v[3] = in->lod; /* the eye's w: the level (glsl/shade_fs.glsl) */
    for (int k = 0; k < r->nlights; k++)
      frame_light_local(in->inv, &r->lights[k], v + 4 + 4 * k);
  }
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->inst_models);
  glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0,
                  (GLsizeiptr)(n * 16 * sizeof(float)), models);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->inst_shading);
  glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0,
                  (GLsizeiptr)(n * VIEW_FLOATS * sizeof(float)), views);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  free(models);
  free(views);
  return satf_gl_check("instance data", err);
}

size_t frame_instance_view_bytes(void) { return VIEW_FLOATS * sizeof(float); }

/* Centre and radius (a little more) of the scene bounds. */
static float scene_radius(const satf_renderer *r, float centre[3]) {
  float d2 = 0.0f;
  for (int a = 0; a < 3; a++) {
    centre[a] = 0.5f * (r->lo[a] + r->hi[a]);
    float h = 0.5f * (r->hi[a] - r->lo[a]);
    d2 += h * h;
  }
  return sqrtf(d2) + 1e-3f;
}

/* Distance squared between two points. */
static float distance2(const float a[3], const float b[3]) {
  float d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  return satf_dot3f(d, d);
}

/* The diameter of the hair the deep opacity map counts: the strands' median
 * width where strands are drawn (the strand reference, else the sparse
 * clusters' strands), else the clusters' density strand diameter
 * (strand_width x radius, their mean); 0 if none says. */
static float hair_diameter(const satf_renderer *r) {
  const strands_gpu *s = r->strands ? r->strands : r->sparse;
  if (s && strands_gpu_width(s) > 0.0f)
    return strands_gpu_width(s);
  double sum = 0.0;
  int n = 0;
  for (int m = 0; m < r->nprotos; m++) {
    const satf_scene_cluster *c = &r->scene->macro_clusters[m].prototype;
    if (c->density.type != SATF_SCENE_DENSITY_PROCEDURAL ||
        !(c->density.strand_width > 0.0f))
      continue;
    sum += (double)c->density.strand_width * c->a.values[0];
    n++;
  }
  return n > 0 ? (float)(sum / n) : 0.0f;
}

/* An orthographic view along the key light's direction (a point light is
 * treated as directional from its position towards the scene centre), and
 * slabs a third of a typical cluster's radius deep, in depth units, but
 * never thinner than one hair. The map (Yuksel & Keyser 2008) counts the
 * hair in four slabs behind the first hair and lumps all that lies beyond
 * into the fourth; the physical mode looks it up one slab nearer the light
 * so a strand does not count itself (strand_fs.glsl). A hair is an
 * occluder one diameter deep: slabs thinner than that put the four inside
 * the first hair, so every point past it counts the whole column (its own
 * strand and the hair beyond it) and its direct light e^-n loses at least
 * e^-1. Clusters split into single strands (import_refine.c) have a
 * strand's radius, which made the slabs a sixth of a strand (the ponytail
 * back-lit: direct light through the map 0.70 of Cycles' unblocked
 * fraction, the frame 0.60 of Cycles' luminance; at one diameter 0.93). */
void frame_light_view(satf_renderer *r) {
  float c[3], rad = scene_radius(r, c), lv[4], dir[3];
  frame_light_vector(&r->lights[0], lv);
  for (int a = 0; a < 3; a++)
    dir[a] = lv[3] != 0.0f ? lv[a] - c[a] : lv[a];
  if (!(satf_normalize3f(dir) > 0)) {
    dir[0] = dir[2] = 0.0f;
    dir[1] = 1.0f;
  }
  float eye[3] = {c[0] + 2 * rad * dir[0], c[1] + 2 * rad * dir[1],
                  c[2] + 2 * rad * dir[2]};
  float up[3] = {0, 1, 0};
  if (fabsf(dir[1]) > 0.95f) {
    up[1] = 0;
    up[2] = 1;
  }
  float view[16], proj[16];
  satf_mat4_look_at(eye, c, up, view);
  satf_mat4_ortho(-rad, rad, -rad, rad, rad, 3 * rad, proj);
  satf_mat4_mul(proj, view, r->light_viewproj);
  float cluster_r = 0.0f;
  for (int m = 0; m < r->nprotos; m++)
    cluster_r += r->scene->macro_clusters[m].prototype.a.values[0];
  cluster_r /= (float)(r->nprotos > 0 ? r->nprotos : 1);
  float slab = 0.66f * cluster_r * 0.5f, hair = hair_diameter(r);
  r->dom_slab = (slab > hair ? slab : hair) / (2.0f * rad);
}

/* The camera's view-projection; without explicit clip planes they hug the
 * scene bounds. */
void frame_camera(const satf_renderer *r, float viewproj[16]) {
  float view[16], proj[16];
  frame_view_proj(r, view, proj);
  /* the anti-aliasing sample's sub-pixel offset (samples.c), as a shift of
   * normalised device coordinates: x_ndc += 2 dx / width */
  float dx = 2.0f * r->jitter[0] / (float)r->width;
  float dy = 2.0f * r->jitter[1] / (float)r->height;
  for (int k = 0; k < 4; k++) {
    proj[k] += dx * proj[12 + k];
    proj[4 + k] += dy * proj[12 + k];
  }
  satf_mat4_mul(proj, view, viewproj);
}

void frame_view_proj(const satf_renderer *r, float view[16], float proj[16]) {
  const satf_scene_camera *cam = &r->camera;
  float c[3], rad = scene_radius(r, c);
  float n = cam->near_clip, f = cam->far_clip;
  if (!(n > 0.0f && f > n)) {
    float d = sqrtf(distance2(cam->position, c));
    f = d + 1.5f * rad;
    n = d - 1.5f * rad;
    if (n < 0.002f * f)
      n = 0.002f * f;
  }
  satf_mat4_look_at(cam->position, cam->target, cam->up, view);
  satf_mat4_perspective(cam->fov_y, (float)r->width / (float)r->height, n, f,
                        proj);
}

/* The whole frame when a corner of the bounds is behind the eye. */
void frame_screen_box(const satf_renderer *r, const float viewproj[16],
                      int box[4]) {
  float mn[2] = {1e30f, 1e30f}, mx[2] = {-1e30f, -1e30f};
  int behind = 0;
  for (int c = 0; c < 8; c++) {
    float p[3] = {c & 1 ? r->hi[0] : r->lo[0], c & 2 ? r->hi[1] : r->lo[1],
                  c & 4 ? r->hi[2] : r->lo[2]};
    float w = viewproj[12] * p[0] + viewproj[13] * p[1] + viewproj[14] * p[2] +
              viewproj[15];
    if (w <= 1e-6f) {
      behind = 1;
      break;
    }
    for (int a = 0; a < 2; a++) {
      float q = (viewproj[4 * a] * p[0] + viewproj[4 * a + 1] * p[1] +
                 viewproj[4 * a + 2] * p[2] + viewproj[4 * a + 3]) /
                w;
      mn[a] = q < mn[a] ? q : mn[a];
      mx[a] = q > mx[a] ? q : mx[a];
    }
  }
  int size[2] = {r->width, r->height};
  for (int a = 0; a < 2; a++) {
    int lo = behind ? 0 : (int)floorf((mn[a] * 0.5f + 0.5f) * size[a]) - 1;
    int hi = behind ? size[a] : (int)ceilf((mx[a] * 0.5f + 0.5f) * size[a]) + 1;
    lo = lo < 0 ? 0 : lo > size[a] ? size[a] : lo;
    hi = hi < lo ? lo : hi > size[a] ? size[a] : hi;
    box[a] = lo;
    box[2 + a] = hi - lo;
  }
}

typedef struct depth_key {
  float d2;
  float centre[3];
  int index;
} depth_key;

/* Far first; equal distances by position, never by list order. */
static int farther_first(const void *a, const void *b) {
  const depth_key *x = a, *y = b;
  if (x->d2 != y->d2)
    return x->d2 < y->d2 ? 1 : -1;
  for (int k = 0; k < 3; k++)
    if (x->centre[k] != y->centre[k])
      return x->centre[k] < y->centre[k] ? -1 : 1;
  return 0;
}

int *frame_far_to_near(const satf_renderer *r) {
  depth_key *keys = malloc((size_t)r->ninsts * sizeof *keys);
  int *order = malloc((size_t)r->ninsts * sizeof *order);
  if (!keys || !order) {
    free(keys);
    free(order);
    return NULL;
  }
  for (int i = 0; i < r->ninsts; i++) {
    const float *c = r->insts[i].centre;
    keys[i].d2 = distance2(c, r->camera.position);
    memcpy(keys[i].centre, c, sizeof keys[i].centre);
    keys[i].index = i;
  }
  qsort(keys, (size_t)r->ninsts, sizeof *keys, farther_first);
  for (int i = 0; i < r->ninsts; i++)
    order[i] = keys[i].index;
  free(keys);
  return order;
}
