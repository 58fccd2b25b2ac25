/* scene.c - the in-memory scene: lifetime, warnings, the database path,
 * the Table-1 totals and the strand width the density assumes. */
#include "satf/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene_anim.h"

static void free_cluster(satf_scene_cluster *c) {
  free(c->trajectory);
  free(c->a.values);
  free(c->b.values);
  free(c->twist.values);
  free(c->density.vdb_file);
  free(c->density.vdb_grid);
  free(c->density.track_first);
  free(c->density.track_count);
  free(c->density.track_xy);
  free(c->density.track_ends);
  free(c->density.track_width);
}

void satf_scene_destroy(satf_scene *scene) {
  if (!scene)
    return;
  for (int i = 0; i < scene->n_macro_clusters; i++) {
    satf_scene_macro_cluster *mc = &scene->macro_clusters[i];
    free(mc->name);
    free_cluster(&mc->prototype);
    free(mc->instances);
  }
  free(scene->macro_clusters);
  for (int i = 0; i < scene->n_meshes; i++)
    free(scene->meshes[i].file);
  free(scene->meshes);
  scene_anim_destroy(scene->animation);
  free(scene->lights);
  for (int i = 0; i < scene->n_warnings; i++)
    free(scene->warnings[i]);
  free(scene->warnings);
  free(scene->database);
  free(scene->strands_file);
  free(scene->description);
  free(scene->name);
  free(scene);
}

int satf_scene_warning_count(const satf_scene *scene) {
  return scene ? scene->n_warnings : 0;
}

const char *satf_scene_warning(const satf_scene *scene, int index) {
  if (!scene || index < 0 || index >= scene->n_warnings)
    return NULL;
  return scene->warnings[index];
}

satf_status satf_scene_set_database(satf_scene *scene, const char *path,
                                    satf_error *err) {
  if (!scene || !path || !path[0])
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "satf_scene_set_database: empty database path");
  size_t n = strlen(path) + 1;
  char *copy = malloc(n);
  if (!copy)
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory",
                          scene->name);
  memcpy(copy, path, n);
  free(scene->database);
  scene->database = copy;
  return SATF_OK;
}

int satf_scene_cluster_curve_count(const satf_scene_cluster *cluster) {
  int n = cluster->a.count;
  if (cluster->b.count > n)
    n = cluster->b.count;
  if (cluster->twist.count > n)
    n = cluster->twist.count;
  return n;
}

void satf_scene_curve_expand(const satf_scene_curve *curve, int n, float *out) {
  for (int i = 0; i < n; i++)
    out[i] = curve->values[curve->count == 1 ? 0 : i];
}

uint64_t satf_scene_cluster_hsv_count(const satf_scene_cluster *cluster) {
  /* SATF eq. 3: st steps along t times su sectors around u, per layer. */
  return (uint64_t)cluster->shell.layers * (uint64_t)cluster->shell.st *
         (uint64_t)cluster->shell.su;
}

uint64_t satf_scene_cluster_count(const satf_scene *scene) {
  uint64_t n = 0;
  for (int i = 0; i < scene->n_macro_clusters; i++)
    n += (uint64_t)scene->macro_clusters[i].n_instances;
  return n;
}

uint64_t satf_scene_layer_count(const satf_scene *scene) {
  uint64_t n = 0;
  for (int i = 0; i < scene->n_macro_clusters; i++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[i];
    n += (uint64_t)mc->n_instances * (uint64_t)mc->prototype.shell.layers;
  }
  return n;
}

size_t satf_scene_track_points(const satf_scene_density *density) {
  size_t n = 0;
  for (int k = 0; density->type == SATF_SCENE_DENSITY_TRACKS &&
                  density->track_count && k < density->n_tracks;
       k++)
    n += (size_t)density->track_count[k];
  return n;
}

int satf_scene_tracks_as_strands(int slices, int n_tracks,
                                 const int *track_count, int max_strands) {
  if (max_strands <= 0 || n_tracks <= 0 || slices < 2)
    return 0;
  if (n_tracks <= max_strands)
    return 1;
  long long crossed = 0;
  for (int k = 0; k < n_tracks; k++)
    crossed += track_count[k];
  /* a tuft (generated fur: 0.16-0.34 of the slices, 10th to 90th
   * percentile; the shared ponytail's clusters 0.85-0.95) */
  return 2 * crossed <= (long long)n_tracks * slices;
}

uint64_t satf_scene_hsv_count(const satf_scene *scene) {
  uint64_t n = 0;
  for (int i = 0; i < scene->n_macro_clusters; i++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[i];
    n += (uint64_t)mc->n_instances *
         satf_scene_cluster_hsv_count(&mc->prototype);
  }
  return n;
}

uint64_t satf_scene_strand_count(const satf_scene *scene) {
  uint64_t n = 0;
  for (int i = 0; i < scene->n_macro_clusters; i++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[i];
    if (mc->prototype.density.type == SATF_SCENE_DENSITY_PROCEDURAL)
      n += (uint64_t)mc->n_instances * (uint64_t)mc->prototype.density.strands;
    else if (mc->prototype.density.type == SATF_SCENE_DENSITY_TRACKS)
      n += (uint64_t)mc->n_instances * (uint64_t)mc->prototype.density.n_tracks;
  }
  return n;
}

static float curve_mean(const satf_scene_curve *c) {
  double sum = 0.0;
  for (int i = 0; i < c->count; i++)
    sum += c->values[i];
  return c->count > 0 ? (float)(sum / c->count) : 0.0f;
}

static int float_less(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

/* The strand diameter the clusters' density assumes (what satf-import
 * estimates from the strands' spacing: "strand_width" in units of the
 * cluster radius sqrt(mean a * mean b), world sigma = width * radius / 2,
 * import_density.c), the median over the placed clusters; 0 if none. */
float satf_scene_density_strand_width(const satf_scene *scene) {
  int n = 0;
  for (int m = 0; m < scene->n_macro_clusters; m++)
    n += scene->macro_clusters[m].n_instances;
  float *w = malloc((size_t)(n > 0 ? n : 1) * sizeof(float));
  if (!w)
    return 0.0f;
  int k = 0;
  for (int m = 0; m < scene->n_macro_clusters; m++) {
    const satf_scene_cluster *c = &scene->macro_clusters[m].prototype;
    if (c->density.type != SATF_SCENE_DENSITY_PROCEDURAL)
      continue;
    float radius = sqrtf(curve_mean(&c->a) * curve_mean(&c->b));
    for (int i = 0; i < scene->macro_clusters[m].n_instances; i++) {
      const float *t = scene->macro_clusters[m].instances[i].m;
      float det = t[0] * (t[5] * t[10] - t[6] * t[9]) -
                  t[1] * (t[4] * t[10] - t[6] * t[8]) +
                  t[2] * (t[4] * t[9] - t[5] * t[8]);
      w[k++] = c->density.strand_width * radius * cbrtf(fabsf(det));
    }
  }
  qsort(w, (size_t)k, sizeof *w, float_less);
  float median = k > 0 ? w[k / 2] : 0.0f;
  free(w);
  return median;
}
