/* budget.c - what the renderer will take for a scene, before anything is
 * built (satf_render_memory_estimate, satf/render.h). */
#include "maps_fiber.h"
#include "maps_gpu_bytes.h"
#include "renderer_internal.h"
#include "satf/render.h"

#include <string.h>
#include <sys/stat.h>

/* Per item, from what the renderer measurably takes (llvmpipe, peak RSS of
 * satf-render with Mesa's shader cache off, fitted over the samples,
 * imported hair and generated fur and a curtain, both shadings:
 * docs/performance.md, "Memory"). A cluster drawn as shells: per HSV of
 * its prototype the sector features, neighbours, shell geometry and
 * proxies (an instance shares them), and per instance its maps as laid
 * out (maps_bytes). */
#define BYTES_PER_PROTO_HSV 700.0
/* Per instance of a cluster, drawn either way: its proxy's and strands'
 * GL buffers and its instance data */
#define BYTES_PER_INSTANCE 60e3
/* Per HSV of a cluster drawn as its strands (hierarchy_sparse at the
 * renderer's default SATF_SPARSE_STRANDS_DEFAULT): its shell geometry and
 * proxies only, no features' neighbours or maps; and per point of its
 * strands (tracks), rebuilt, their ribbons, light and what llvmpipe bins
 * of their segments. A lower --sparse-strands draws more of them as
 * clusters. */
#define BYTES_PER_SPARSE_HSV 320.0
#define BYTES_PER_SPARSE_POINT 650.0
#define BYTES_PER_STRAND 36.0
/* per pixel the fragment arrays of exact compositing at the START_SLOTS
 * they keep while the pool past them holds the rest (lists.h), their
 * counters, the pool, and the frame targets */
#define BYTES_PER_PIXEL 320.0
/* A VDB grid in memory over its file's size: the file stores leaves
 * compressed and the tree adds its internal nodes. */
#define VDB_MEMORY_PER_FILE_BYTE 3.0
/* What any renderer takes whatever the scene and database: the GL
 * driver, shaders and the program itself; and what the physical mode's
 * programs and tables add. */
#define BYTES_FIXED 175e6
#define BYTES_FIXED_PHYSICAL 30e6
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
 * (the renderer reads each once however many clusters name it). */
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
  }
  return sum;
}

/* An instance's maps of cluster c, with records `width` samples wide in
 * `quads` RGBA half quads a texel: the CPU's copy (maps.h) and the GL
 * texture's layers (hierarchy.c, rows for st up to a multiple of 4). */
/* An HSV's texels in the CPU's copy of the maps (hierarchy.c: inst.texels),
 * `quads` RGBA half quads a texel. */
static double hsv_copy_bytes(int width, int quads) {
  return (double)maps_hsv_texels(width) * quads * 4.0 * sizeof(uint16_t);
}

static double maps_bytes(const satf_scene_cluster *c, int width, int quads) {
  const satf_scene_shell *sh = &c->shell;
  double hsvs = (double)satf_scene_cluster_hsv_count(c);
  double gl = (double)sh->layers * sh->su * width * hierarchy_map_rows(sh->st) *
              quads * 4.0 * sizeof(uint16_t);
  return hsvs * hsv_copy_bytes(width, quads) + gl;
}

/* Every HSV, those of clusters drawn as strands (at the sparse-strands
 * setting `sparse`) at their own rate; the maps with records `width`
 * samples wide in `quads` quads a texel. Width 0, the database not known:
 * a lower bound, the maps not counted and a cluster that may be drawn as
 * its strands at the cheaper of its two ways. */
static double hsv_bytes(const satf_scene *scene, int sparse, int width,
                        int quads) {
  double sum = 0.0;
  for (int m = 0; m < scene->n_macro_clusters; m++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[m];
    double hsvs = (double)satf_scene_cluster_hsv_count(&mc->prototype);
    double inst = (double)mc->n_instances;
    /* world-space density gives every instance its own features and
     * neighbours (hierarchy.c) */
    double own =
        mc->prototype.density.type == SATF_SCENE_DENSITY_VDB ? inst : 1.0;
    double shells =
        BYTES_PER_PROTO_HSV * own * hsvs +
        (width > 0 ? inst * maps_bytes(&mc->prototype, width, quads) : 0.0);
    if (hierarchy_sparse(&mc->prototype, sparse)) {
      double strands =
          inst * (BYTES_PER_SPARSE_HSV * hsvs +
                  BYTES_PER_SPARSE_POINT *
                      (double)satf_scene_track_points(&mc->prototype.density));
      sum += width > 0 || strands < shells ? strands : shells;
    } else
      sum += shells;
    sum += BYTES_PER_INSTANCE * inst;
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
 * M_p's table and the orientation-free levels (maps_fiber.c); each with
 * its records as halfs beside the floats, which the look-ups blend
 * (satf_db_index). */
static double database_bytes(const satf_scene *scene, const satf_db *db) {
  const satf_build_params *p = satf_db_params(db);
  double halfs = 1.0 + (double)sizeof(uint16_t) / sizeof(float);
  double sum = halfs * record_bytes(p, satf_db_channels(db));
  maps_fiber_shape f;
  if (physical(scene, db, &f))
    sum += halfs * record_bytes(p, f.channels) +
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
  double per_hsv_copy = hsv_copy_bytes(satf_db_width(db), fiber ? 2 : 1);
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
      640, 480, NULL, SATF_MAPS_DEFAULT, SATF_SPARSE_STRANDS_DEFAULT, 0};
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
    maps_fiber_shape f;
    int fiber = opt->db && physical(scene, opt->db, &f);
    m.hsvs = hsv_bytes(scene, sparse, opt->db ? satf_db_width(opt->db) : 0,
                       fiber ? 2 : 1);
    m.strand_path = strand_path_bytes(scene, sparse, opt->strand_points);
    m.strands = BYTES_PER_STRAND * (double)satf_scene_strand_count(scene);
    m.pixels = BYTES_PER_PIXEL * (double)opt->width * (double)opt->height;
    m.vdb = vdb_bytes(scene);
    if (opt->db) {
      m.database = database_bytes(scene, opt->db);
      if (opt->maps == SATF_MAPS_GPU)
        m.gpu_maps = gpu_maps_bytes(scene, opt->db, sparse);
    }
    m.fixed = BYTES_FIXED + (fiber ? BYTES_FIXED_PHYSICAL : 0.0);
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
