/* import_scene.c - fitted clusters as a scene (satf/scene.h): one
 * macro-cluster per prototype with an instance per member cluster, each
 * prototype's density procedural (its real strand count, the estimated
 * strand width and layout) or the hairstyle's OpenVDB grid, a camera
 * framing the hair, a key and a fill light. The scene library writes it. */
#define _POSIX_C_SOURCE 200809L
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "import_internal.h"
#include "satf/math.h"

/* A number rounded to 7 significant digits, so the file stays readable and
 * floats do not print as 9-digit ones. */
static float round7(double v) {
  char buf[32];
  snprintf(buf, sizeof buf, "%.7g", v);
  return (float)strtod(buf, NULL);
}

static float *rounded(const float *v, int n, int *failed) {
  float *out = malloc((size_t)(n > 0 ? n : 1) * sizeof *out);
  if (!out) {
    *failed = 1;
    return NULL;
  }
  for (int i = 0; i < n; i++)
    out[i] = round7(v[i]);
  return out;
}

static void *copy_bytes(const void *from, size_t size, int *failed) {
  void *to = malloc(size ? size : 1);
  if (!to)
    *failed = 1;
  else if (size)
    memcpy(to, from, size);
  return to;
}

static char *copy_string(const char *s, int *failed) {
  char *c = s ? malloc(strlen(s) + 1) : NULL;
  if (c)
    strcpy(c, s);
  else if (s)
    *failed = 1;
  return c;
}

/* base_dir + "/" + path for a relative path: what the loader will make of
 * the path the file names. */
static char *scene_path(const char *base_dir, const char *path, int *failed) {
  if (!path || !base_dir || path[0] == '/')
    return copy_string(path, failed);
  char *out = malloc(strlen(base_dir) + strlen(path) + 2);
  if (!out) {
    *failed = 1;
    return NULL;
  }
  sprintf(out, "%s%s%s", base_dir,
          base_dir[strlen(base_dir) - 1] == '/' ? "" : "/", path);
  return out;
}

static void fill_cluster(const satf_import_fit *f,
                         const satf_import_scene_options *o,
                         const char *base_dir, uint64_t seed,
                         satf_scene_cluster *c, int *failed) {
  c->n_points = f->n_ctrl;
  c->trajectory = rounded(f->traj, 3 * f->n_ctrl, failed);
  satf_scene_curve *curves[3] = {&c->a, &c->b, &c->twist};
  const float *values[3] = {f->a, f->b, f->twist};
  for (int i = 0; i < 3; i++) {
    curves[i]->count = f->n_radius;
    curves[i]->values = rounded(values[i], f->n_radius, failed);
  }
  c->shell = satf_import_choose_shell(f);
  c->shell.core = round7(c->shell.core);
  satf_scene_density *d = &c->density;
  if (o && o->vdb_file) {
    d->type = SATF_SCENE_DENSITY_VDB;
    d->vdb_file = scene_path(base_dir, o->vdb_file, failed);
    d->vdb_grid = copy_string(o->vdb_grid ? o->vdb_grid : "density", failed);
    return;
  }
  d->strand_width = round7(f->strand_width);
  /* curly strands (their median curl above 0: import_curl.c) cross their
   * trajectory at the median angle of their points' tangents to it */
  if (f->curl > 0.0f)
    d->curl = round7(fminf(f->measures.direction[0], 90.0f));
  d->scale = round7(satf_import_density_scale(
      f->strand_width, (1.0f - c->shell.core) / (float)c->shell.layers));
  if (f->n_tracks > 0) { /* the cluster's own strands (tracks) */
    size_t points = 0;
    for (int k = 0; k < f->n_tracks; k++)
      points += (size_t)f->track_count[k];
    d->type = SATF_SCENE_DENSITY_TRACKS;
    d->track_slices = f->track_slices;
    d->n_tracks = f->n_tracks;
    d->track_first =
        copy_bytes(f->track_first, (size_t)f->n_tracks * sizeof(int), failed);
    d->track_count =
        copy_bytes(f->track_count, (size_t)f->n_tracks * sizeof(int), failed);
    d->track_xy = copy_bytes(f->track_xy, 2 * points * sizeof(float), failed);
    if (f->track_ends)
      d->track_ends = copy_bytes(
          f->track_ends, 6 * (size_t)f->n_tracks * sizeof(float), failed);
    if (f->track_width)
      d->track_width = rounded(f->track_width, f->n_tracks, failed);
    return;
  }
  d->type = SATF_SCENE_DENSITY_PROCEDURAL;
  d->strands = f->strands;
  d->seed = seed;
  d->layout = f->layout;
  /* the procedural model's range (the tracks' reaches 2) */
  d->strand_width = round7(f->strand_width < 0.5f ? f->strand_width : 0.5f);
  d->gradient = round7(f->gradient);
}

/* The box around every trajectory's control points grown by the largest
 * half-axis (a B-spline stays inside its control points' hull). */
static void fits_bounds(const satf_import_fit *fits, int n, double lo[3],
                        double hi[3]) {
  for (int c = 0; c < 3; c++) {
    lo[c] = DBL_MAX;
    hi[c] = -DBL_MAX;
  }
  for (int i = 0; i < n; i++) {
    double r = 0.0;
    for (int j = 0; j < fits[i].n_radius; j++)
      r = fmax(r, fmax(fits[i].a[j], fits[i].b[j]));
    for (int k = 0; k < fits[i].n_ctrl; k++)
      for (int c = 0; c < 3; c++) {
        lo[c] = fmin(lo[c], fits[i].traj[3 * k + c] - r);
        hi[c] = fmax(hi[c], fits[i].traj[3 * k + c] + r);
      }
  }
}

static void frame_camera(const satf_import_fit *fits, int n,
                         const satf_import_scene_options *o,
                         satf_scene_camera *cam) {
  double lo[3], hi[3];
  if (o && o->frame_lo && o->frame_hi)
    for (int c = 0; c < 3; c++) {
      lo[c] = o->frame_lo[c];
      hi[c] = o->frame_hi[c];
    }
  else
    fits_bounds(fits, n, lo, hi);
  /* the box's diagonal sphere wastes most of the frame on hair that is
   * long and thin; its largest half-extent with a margin frames it */
  double c[3], r = 0.0;
  for (int k = 0; k < 3; k++) {
    c[k] = 0.5 * (lo[k] + hi[k]);
    r = fmax(r, 0.5 * (hi[k] - lo[k]));
  }
  r *= 1.15;
  const double fov = 35.0;
  double dist = 1.05 * r / sin(0.5 * fov * SATF_PI / 180.0);
  double dir[3] = {0.3, 0.2, 1.0};
  double len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
  memset(cam, 0, sizeof *cam);
  for (int k = 0; k < 3; k++) {
    cam->position[k] = round7(c[k] + dist * dir[k] / len);
    cam->target[k] = round7(c[k]);
  }
  cam->up[1] = 1.0f;
  cam->fov_y = round7(fov);
}

static void directional(double dx, double dy, double dz, double r, double g,
                        double b, double intensity, satf_scene_light *l) {
  l->type = SATF_SCENE_LIGHT_DIRECTIONAL;
  float d[3] = {round7(dx), round7(dy), round7(dz)};
  satf_scene_normalize(d); /* as the loader would */
  memcpy(l->direction, d, sizeof d);
  l->color[0] = round7(r);
  l->color[1] = round7(g);
  l->color[2] = round7(b);
  l->intensity = round7(intensity);
}

/* Image, camera, lights, background, description, database and mesh. */
static satf_status fill_view(satf_scene *scene, const satf_import_fit *fits,
                             int n, const satf_import_scene_options *o,
                             const char *base_dir, satf_error *err) {
  scene->image.width = o && o->width ? o->width : 640;
  scene->image.height = o && o->height ? o->height : 480;
  frame_camera(fits, n, o, &scene->camera);
  satf_scene_light *lights = calloc(2, sizeof *lights);
  if (!lights)
    return satf_error_set(err, SATF_ERR_NOMEM, "scene: out of memory");
  free(scene->lights);
  scene->lights = lights;
  scene->n_lights = 2;
  directional(-0.45, -0.6, -0.66, 1.0, 0.97, 0.92, 1.0, &lights[0]);
  directional(0.8, -0.1, -0.6, 0.75, 0.82, 1.0, 0.3, &lights[1]);
  scene->background[0] = round7(0.16);
  scene->background[1] = round7(0.17);
  scene->background[2] = round7(0.2);
  int failed = 0;
  scene->description = copy_string(o ? o->description : NULL, &failed);
  scene->database = scene_path(base_dir, o ? o->database : NULL, &failed);
  if (failed)
    return satf_error_set(err, SATF_ERR_NOMEM, "scene: out of memory");
  if (o && o->mesh_file) { /* drawn opaque, occluding and shadowing hair */
    char *mesh = scene_path(base_dir, o->mesh_file, &failed);
    satf_status s =
        mesh ? satf_scene_add_mesh(scene, mesh, err)
             : satf_error_set(err, SATF_ERR_NOMEM, "scene: out of memory");
    free(mesh);
    return s;
  }
  return SATF_OK;
}

static satf_status fill_macro_clusters(satf_scene *scene,
                                       const satf_import_fit *fits, int n,
                                       const satf_import_macro *macro,
                                       const satf_import_scene_options *o,
                                       const char *base_dir, satf_error *err) {
  int n_macro = macro ? macro->n_macro : n, failed = 0;
  uint64_t seed = o ? o->seed : 1;
  scene->macro_clusters =
      calloc((size_t)n_macro, sizeof *scene->macro_clusters);
  /* each macro-cluster's instances sized to its own count: room for all n
   * clusters in each took n_macro x n instances (1.3 GB and 10 s for 8192
   * clusters of short strands in 4380 macro-clusters) */
  int *count = calloc((size_t)n_macro, sizeof *count);
  if (!scene->macro_clusters || !count) {
    free(count);
    return satf_error_set(err, SATF_ERR_NOMEM, "scene: out of memory");
  }
  scene->n_macro_clusters = n_macro;
  for (int c = 0; c < n; c++)
    count[macro ? macro->macro_of[c] : c]++;
  for (int m = 0; m < n_macro && !failed; m++) {
    satf_scene_macro_cluster *mc = &scene->macro_clusters[m];
    int proto = macro ? macro->prototype[m] : m;
    char name[64];
    snprintf(name, sizeof name, "cluster %d", proto);
    mc->name = copy_string(name, &failed);
    fill_cluster(&fits[proto], o, base_dir, seed + (uint64_t)m, &mc->prototype,
                 &failed);
    mc->instances = calloc((size_t)count[m], sizeof *mc->instances);
    failed |= !mc->instances;
  }
  free(count);
  /* the instances in cluster order, as before */
  for (int c = 0; c < n && !failed; c++) {
    int m = macro ? macro->macro_of[c] : c;
    satf_scene_macro_cluster *mc = &scene->macro_clusters[m];
    int proto = macro ? macro->prototype[m] : m;
    float *to = mc->instances[mc->n_instances++].m;
    for (int k = 0; k < 16; k++)
      to[k] = c != proto ? round7(macro->transform[16 * (size_t)c + k])
                         : (k % 5 == 0 ? 1.0f : 0.0f);
  }
  return failed ? satf_error_set(err, SATF_ERR_NOMEM, "scene: out of memory")
                : SATF_OK;
}

satf_status satf_import_scene_build(const satf_import_fit *fits, int n,
                                    const satf_import_macro *macro,
                                    const satf_import_scene_options *o,
                                    const char *path, satf_scene **out,
                                    satf_error *err) {
  *out = NULL;
  if (n < 1 || (macro && macro->n_clusters != n))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "scene: %d clusters and a macro-cluster table for "
                          "%d",
                          n, macro ? macro->n_clusters : n);
  char *base_dir = NULL;
  const char *slash = path ? strrchr(path, '/') : NULL;
  if (slash) {
    size_t len = slash == path ? 1 : (size_t)(slash - path);
    if (!(base_dir = malloc(len + 1)))
      return satf_error_set(err, SATF_ERR_NOMEM, "scene: out of memory");
    memcpy(base_dir, path, len);
    base_dir[len] = '\0';
  }
  satf_scene *scene = NULL;
  satf_status s =
      satf_scene_create(path ? path : "<imported scene>", &scene, err);
  if (s == SATF_OK)
    s = fill_view(scene, fits, n, o, base_dir, err);
  if (s == SATF_OK)
    s = fill_macro_clusters(scene, fits, n, macro, o, base_dir, err);
  free(base_dir);
  if (s != SATF_OK) {
    satf_scene_destroy(scene);
    return s;
  }
  *out = scene;
  return SATF_OK;
}

satf_status satf_import_scene_json(const satf_import_fit *fits, int n,
                                   const satf_import_macro *macro,
                                   const satf_import_scene_options *o,
                                   char **json, satf_error *err) {
  *json = NULL;
  satf_scene *scene;
  satf_status s = satf_import_scene_build(fits, n, macro, o, NULL, &scene, err);
  if (s == SATF_OK)
    s = satf_scene_to_json(scene, NULL, json, err);
  satf_scene_destroy(scene);
  return s;
}

satf_status satf_import_write_scene(const char *path,
                                    const satf_import_fit *fits, int n,
                                    const satf_import_macro *macro,
                                    const satf_import_scene_options *o,
                                    satf_error *err) {
  satf_scene *scene;
  satf_status s = satf_import_scene_build(fits, n, macro, o, path, &scene, err);
  if (s == SATF_OK)
    s = satf_scene_write(scene, path, err);
  satf_scene_destroy(scene);
  return s;
}
