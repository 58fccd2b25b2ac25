/* budget.c - what the renderer will take for a scene, before anything is
 * built (satf_render_memory_estimate, satf/render.h). */
#include "renderer_internal.h"
#include "satf/render.h"

#include <string.h>
#include <sys/stat.h>

/* Per item, from what the renderer measurably takes (llvmpipe, peak RSS of
 * satf-render under /usr/bin/time -v over the samples, imported hair and
 * generated fur and curls): per HSV the sector features, neighbours,
 * angles, maps and their textures; per procedural or track strand its
 * base, wobble and bucket entries; per pixel the fragment arrays of exact
 * compositing (64 slots of 16 bytes, their counters and depth keys) and the
 * frame targets. */
#define BYTES_PER_HSV 2000.0
/* Per HSV of a cluster drawn as its strands (hierarchy_sparse at the
 * renderer's default SATF_SPARSE_STRANDS_DEFAULT): its shell geometry and
 * proxies only, no features' neighbours or maps (the shared ponytail's
 * 1.8M such HSVs: about 1.1 to 1.3 GB). A lower --sparse-strands draws more of
 * them as clusters, at BYTES_PER_HSV. */
#define BYTES_PER_SPARSE_HSV 700.0
#define BYTES_PER_STRAND 36.0
#define BYTES_PER_PIXEL 300.0
/* A VDB grid in memory over its file's size: the file stores leaves
 * compressed and the tree adds its internal nodes. */
#define VDB_MEMORY_PER_FILE_BYTE 3.0
/* Per HSV of a cluster with VDB density, on top of BYTES_PER_HSV: world-
 * space density gives every instance its own features and neighbour
 * cache (hierarchy.c). */
#define BYTES_PER_VDB_HSV 1000.0
/* What any renderer takes whatever the scene: the GL driver, shaders,
 * the database's textures and the program itself. */
#define BYTES_FIXED 270e6

/* What VDB density adds: the grids of the distinct files the clusters name
 * (the renderer reads each once however many clusters name it) and the
 * per-instance features of its clusters. */
static double vdb_bytes(const satf_scene *scene) {
  double sum = 0.0;
  for (int m = 0; m < scene->n_macro_clusters; m++) {
    const satf_scene_density *d = &scene->macro_clusters[m].prototype.density;
    if (d->type != SATF_SCENE_DENSITY_VDB || !d->vdb_file)
      continue;
    int seen = 0;
    for (int k = 0; k < m && !seen; k++) {
      const satf_scene_density *e = &scene->macro_clusters[k].prototype.density;
      seen = e->type == SATF_SCENE_DENSITY_VDB && e->vdb_file &&
             !strcmp(e->vdb_file, d->vdb_file) &&
             !strcmp(e->vdb_grid, d->vdb_grid);
    }
    struct stat st;
    if (!seen && stat(d->vdb_file, &st) == 0)
      sum += VDB_MEMORY_PER_FILE_BYTE * (double)st.st_size;
    sum += BYTES_PER_VDB_HSV * (double)scene->macro_clusters[m].n_instances *
           (double)satf_scene_cluster_hsv_count(
               &scene->macro_clusters[m].prototype);
  }
  return sum;
}

/* Every instance's HSVs, those of clusters drawn as strands at their
 * own rate. */
static double hsv_bytes(const satf_scene *scene) {
  double sum = 0.0;
  for (int m = 0; m < scene->n_macro_clusters; m++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[m];
    double per = hierarchy_sparse(&mc->prototype, SATF_SPARSE_STRANDS_DEFAULT)
                     ? BYTES_PER_SPARSE_HSV
                     : BYTES_PER_HSV;
    sum += per * (double)mc->n_instances *
           (double)satf_scene_cluster_hsv_count(&mc->prototype);
  }
  return sum;
}

double satf_render_memory_estimate(const satf_scene *scene, long width,
                                   long height, satf_render_memory *parts) {
  satf_render_memory m;
  memset(&m, 0, sizeof m);
  if (scene) {
    m.hsvs = hsv_bytes(scene);
    m.strands = BYTES_PER_STRAND * (double)satf_scene_strand_count(scene);
    m.pixels = BYTES_PER_PIXEL * (double)width * (double)height;
    m.vdb = vdb_bytes(scene);
    m.fixed = BYTES_FIXED;
    m.total = m.hsvs + m.strands + m.pixels + m.vdb + m.fixed;
  }
  if (parts)
    *parts = m;
  return m.total;
}

/* The largest part, for a refusal that names what to change. */
const char *satf_render_memory_largest(const satf_render_memory *m) {
  const char *name = "HSVs";
  double most = m->hsvs;
  if (m->strands > most)
    most = m->strands, name = "strands";
  if (m->pixels > most)
    most = m->pixels, name = "pixels";
  if (m->vdb > most)
    name = "VDB density";
  return name;
}
