/* budget.c - what the renderer will take for a scene, before anything is
 * built (satf_render_memory_estimate, satf/render.h). */
#include "maps_fiber.h"
#include "maps_gpu_bytes.h"
#include "renderer_internal.h"
#include "satf/render.h"

#include <string.h>
#include <sys/stat.h>

/* Per item, from what the renderer measurably takes (llvmpipe, peak RSS of
 * satf-render under /usr/bin/time -v over the samples, imported hair and
 * generated fur and curls): per HSV the sector features, neighbours,
 * angles, maps and their textures; per procedural or track strand its
 * base, wobble and bucket entries; per pixel the fragment arrays of exact
 * compositing (64 slots of 16 bytes, their counters and depth keys, the
 * pool past them: 20 bytes, lists.h) and the frame targets. */
#define BYTES_PER_HSV 2000.0
/* Per HSV of a cluster drawn as its strands (hierarchy_sparse at the
 * renderer's default SATF_SPARSE_STRANDS_DEFAULT): its shell geometry and
 * proxies only, no features' neighbours or maps (the shared ponytail's
 * 1.8M such HSVs: about 1.1 to 1.3 GB). A lower --sparse-strands draws more of
 * them as clusters, at BYTES_PER_HSV. */
#define BYTES_PER_SPARSE_HSV 700.0
#define BYTES_PER_STRAND 36.0
#define BYTES_PER_PIXEL 320.0
/* A VDB grid in memory over its file's size: the file stores leaves
 * compressed and the tree adds its internal nodes. */
#define VDB_MEMORY_PER_FILE_BYTE 3.0
/* Per HSV of a cluster with VDB density, on top of BYTES_PER_HSV: world-
 * space density gives every instance its own features and neighbour
 * cache (hierarchy.c). */
#define BYTES_PER_VDB_HSV 1000.0
/* What any renderer takes whatever the scene and database: the GL
 * driver, shaders and the program itself (the 270 MB measured with the
 * default database, less its 67 MB of records, now counted apart). */
#define BYTES_FIXED 203e6
/* What compiling the GPU's maps' two compute programs adds to the peak
 * (llvmpipe's LLVM, without Mesa's shader cache: a new database width or
 * hair colour changes their defines, so a scene's first run compiles):
 * hair_7a's peak with MESA_SHADER_CACHE_DISABLE=true over its peak with
 * the programs cached, 89 MB, less the 15 MB the CPU's maps' run adds
 * the same way (its draw programs, in every mode). */
#define BYTES_GPU_PROGRAMS 75e6
/* The strand path (satf_renderer_set_strands) over the clusters' frame,
 * from satf-render --strands against the same scene's clusters (peak RSS,
 * 640x480 and 320x240, physical): straight hair of 10K x 32, 20K x 16,
 * 20K x 32, 20K x 64 and 40K x 32 points, all in shells, took 325, 310,
 * 505, 930 and 1,060 MB over the clusters' estimate: per point its two
 * ribbon vertices, its light and what llvmpipe bins of its segments'
 * triangles, and once the strand pass's programs and buffers, which a
 * scene with clusters drawn as strands (the imported ponytail, fur) has
 * already. The clusters' maps, which the strand path never fills, stay
 * counted: satf-view switches between the two (T). */
#define BYTES_PER_STRAND_POINT 710.0
#define BYTES_STRAND_PATH 90e6

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

/* Every instance's HSVs, those of clusters drawn as strands (at the
 * sparse-strands setting `sparse`) at their own rate. */
static double hsv_bytes(const satf_scene *scene, int sparse) {
  double sum = 0.0;
  for (int m = 0; m < scene->n_macro_clusters; m++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[m];
    double per = hierarchy_sparse(&mc->prototype, sparse) ? BYTES_PER_SPARSE_HSV
                                                          : BYTES_PER_HSV;
    sum += per * (double)mc->n_instances *
           (double)satf_scene_cluster_hsv_count(&mc->prototype);
  }
  return sum;
}

/* Whether the renderer made of scene and db shades with the fibre model
 * (renderer.c: satf_maps_fiber_create); *shape then says what it makes. */
static int physical(const satf_scene *scene, const satf_db *db,
                    maps_fiber_shape *shape) {
  if (scene->material.model != SATF_MATERIAL_PHYSICAL || !scene->effects.satf ||
      satf_db_kind(db) != SATF_RECORD_FIBER)
    return 0;
  maps_fiber_shape_of(db, &scene->material, shape);
  return 1;
}

/* Records of `channels` floats of the database's width. */
static double record_bytes(const satf_build_params *p, int channels) {
  return (double)p->samples * p->n_view * p->n_light * channels *
         p->trace.width * (double)sizeof(float);
}

/* The database as read, and the physical mode's re-levelled copy with
 * M_p's table and the orientation-free levels (maps_fiber.c). */
static double database_bytes(const satf_scene *scene, const satf_db *db) {
  const satf_build_params *p = satf_db_params(db);
  double sum = record_bytes(p, satf_db_channels(db));
  maps_fiber_shape f;
  if (physical(scene, db, &f))
    sum += record_bytes(p, f.channels) +
           (double)(maps_gpu_mp_floats(&f) + maps_gpu_rel_floats(p, &f)) *
               sizeof(float);
  return sum;
}

/* What the GPU's maps add (maps_gpu.c): the records and tables uploaded
 * once, every geometry's sectors and neighbours (once per prototype; per
 * instance with VDB density, which gives each its own), the compute
 * programs; less the CPU's copy of every instance's maps (hierarchy.c:
 * inst.texels, 4 halfs a texel and quad), calloc'ed but never written. */
static double gpu_maps_bytes(const satf_scene *scene, const satf_db *db,
                             int sparse) {
  maps_fiber_shape f;
  int fiber = physical(scene, db, &f);
  maps_gpu_table_bytes t;
  maps_gpu_tables_bytes(db, fiber ? &f : NULL, &t);
  satf_map_options opt = satf_map_options_default();
  int k = maps_gpu_k(&opt);
  double per_hsv_copy = (double)maps_hsv_texels(satf_db_width(db)) * 4.0 *
                        (fiber ? 2.0 : 1.0) * 2.0;
  double sum = (double)(t.records + t.tables) + BYTES_GPU_PROGRAMS;
  for (int m = 0; m < scene->n_macro_clusters; m++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[m];
    if (hierarchy_sparse(&mc->prototype, sparse))
      continue; /* drawn as strands: no maps */
    const satf_scene_shell *sh = &mc->prototype.shell;
    satf_shell_params shell = {sh->layers, sh->st, sh->su, sh->core};
    size_t hsvs = (size_t)satf_scene_cluster_hsv_count(&mc->prototype);
    size_t sectors = satf_shell_sector_count(&shell);
    double geoms = mc->prototype.density.type == SATF_SCENE_DENSITY_VDB
                       ? (double)mc->n_instances
                       : 1.0;
    sum += geoms * (double)(maps_gpu_sector_bytes(sectors) +
                            maps_gpu_neighbor_bytes(sectors, hsvs, k));
    sum -= per_hsv_copy * (double)mc->n_instances * (double)hsvs;
  }
  return sum;
}

/* What drawing `points` source strand points instead of the clusters
 * adds (BYTES_PER_STRAND_POINT). */
static double strand_path_bytes(const satf_scene *scene, int sparse,
                                size_t points) {
  if (points == 0)
    return 0.0;
  int drawn = 0; /* a cluster drawn as its strands: the pass is there */
  for (int m = 0; m < scene->n_macro_clusters && !drawn; m++)
    drawn = hierarchy_sparse(&scene->macro_clusters[m].prototype, sparse);
  return BYTES_PER_STRAND_POINT * (double)points +
         (drawn ? 0.0 : BYTES_STRAND_PATH);
}

satf_render_memory_options satf_render_memory_options_default(void) {
  satf_render_memory_options o = {
      640, 480, NULL, SATF_MAPS_CPU, SATF_SPARSE_STRANDS_DEFAULT, 0};
  return o;
}

double satf_render_memory_estimate(const satf_scene *scene,
                                   const satf_render_memory_options *opt,
                                   satf_render_memory *parts) {
  satf_render_memory m;
  memset(&m, 0, sizeof m);
  if (scene && opt) {
    /* satf_renderer_set_sparse_strands' range */
    int sparse = opt->sparse_strands < 0 ? 0
                 : opt->sparse_strands > SATF_SPARSE_STRANDS_MAX
                     ? SATF_SPARSE_STRANDS_MAX
                     : opt->sparse_strands;
    m.hsvs = hsv_bytes(scene, sparse);
    m.strand_path = strand_path_bytes(scene, sparse, opt->strand_points);
    m.strands = BYTES_PER_STRAND * (double)satf_scene_strand_count(scene);
    m.pixels = BYTES_PER_PIXEL * (double)opt->width * (double)opt->height;
    m.vdb = vdb_bytes(scene);
    if (opt->db) {
      m.database = database_bytes(scene, opt->db);
      if (opt->maps == SATF_MAPS_GPU)
        m.gpu_maps = gpu_maps_bytes(scene, opt->db, sparse);
    }
    m.fixed = BYTES_FIXED;
    m.total = m.hsvs + m.strands + m.pixels + m.vdb + m.database + m.gpu_maps +
              m.strand_path + m.fixed;
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
    most = m->vdb, name = "VDB density";
  if (m->database > most)
    most = m->database, name = "the database";
  if (m->gpu_maps > most)
    most = m->gpu_maps, name = "the GPU's maps";
  if (m->strand_path > most)
    name = "the strand path";
  return name;
}
