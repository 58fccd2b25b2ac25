/* import_run.c - the whole import as satf-import runs it: strands in,
 * clusters (k-means), fitted generalized cylinders, macro-clusters, an
 * optional OpenVDB density grid, and the scene written out (SATF sec.
 * 3.1-3.3), with progress bars and the summary it prints. */
#define _XOPEN_SOURCE 700
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "import_internal.h"
#include "import_prepare.h"
#include "satf/common.h"
#include "satf/math.h"

/* What the steps share. */
typedef struct run {
  const satf_import_options *o;
  satf_import_result *r;
  double t0;
  satf_strand_set *all;
  int *labels;
  satf_import_fit *fits;
  satf_import_fit_params fp;
  satf_import_refine_params rp; /* adaptive clustering (o->clusters == 0) */
  satf_import_macro macro;
  int have_macro;
  char mesh_path[PATH_MAX];
  float mesh_m[16];             /* --mesh-transform */
  float mesh_lo[3], mesh_hi[3]; /* the transformed mesh's bounds */
  char database[PATH_MAX]; /* --db, absolute (the scene names it relative) */
} run;

static void progress_cb(void *ctx, size_t done, size_t total) {
  satf_progress_update(ctx, done, total);
}

/* The bounds of the box lo..hi after the row-major transform m. */
static void transformed_bounds(const float m[16], const float lo[3],
                               const float hi[3], float out_lo[3],
                               float out_hi[3]) {
  for (int c = 0; c < 3; c++) {
    out_lo[c] = INFINITY;
    out_hi[c] = -INFINITY;
  }
  for (int k = 0; k < 8; k++) {
    float p[3] = {k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1],
                  k & 4 ? hi[2] : lo[2]};
    for (int r = 0; r < 3; r++) {
      float v = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] +
                m[4 * r + 3];
      out_lo[r] = fminf(out_lo[r], v);
      out_hi[r] = fmaxf(out_hi[r], v);
    }
  }
}

/* The mesh is checked now, placed by --mesh-transform, and held absolute
 * (satf_scene_write names it relative to the scene). */
static satf_status check_mesh(run *u, satf_error *err) {
  const satf_import_options *o = u->o;
  satf_mesh *probe = NULL;
  satf_error why;
  if (satf_mesh_read(o->mesh, &probe, &why) != SATF_OK)
    return satf_error_set(err, why.status, "--mesh: %s", why.message);
  import_mesh_matrix(o, u->mesh_m);
  float lo[3], hi[3];
  satf_mesh_bounds(probe, lo, hi);
  transformed_bounds(u->mesh_m, lo, hi, u->mesh_lo, u->mesh_hi);
  satf_mesh_destroy(probe);
  if (!realpath(u->o->mesh, u->mesh_path))
    snprintf(u->mesh_path, sizeof u->mesh_path, "%s", u->o->mesh);
  return SATF_OK;
}

/* Every input into u->all; a sequence's first frame defines the clusters. */
static satf_status read_inputs(run *u, satf_error *err) {
  const satf_import_options *o = u->o;
  char first_frame[PATH_MAX];
  if (o->sequence) {
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
    snprintf(first_frame, sizeof first_frame, o->inputs[0], (int)o->first);
#pragma GCC diagnostic pop
  }
  u->r->follow = -1;
  for (int i = 0; i < o->n_inputs; i++) {
    satf_strand_set *s, *both;
    int followers;
    satf_status st = satf_import_read_strands_followed(
        o->sequence ? first_frame : o->inputs[i], o, &s, &followers, err);
    int dropped = 0;
    size_t merged = 0;
    if (st == SATF_OK && !o->sequence) /* a sequence keeps its strands */
      st = import_prepare_strands(&s, NULL, 1, o->inputs[i], &dropped, &merged,
                                  err);
    if (st != SATF_OK) {
      satf_strand_set_destroy(s);
      return st;
    }
    u->r->dropped_strands += dropped;
    u->r->merged_points += merged;
    if (followers >= 0) {
      if (u->r->follow < 0)
        u->r->follow = followers;
      u->r->guides += satf_strand_set_count(s) / (followers + 1);
    }
    /* The budget, before anything grows with the points. */
    size_t total = satf_strand_set_point_count(s) +
                   (u->all ? satf_strand_set_point_count(u->all) : 0);
    char what[PATH_MAX + 32];
    snprintf(what, sizeof what, "%s%s", o->inputs[0],
             o->n_inputs > 1 ? " (and the other inputs)" : "");
    if ((st = satf_import_check_budget(o, what, total, err)) != SATF_OK) {
      satf_strand_set_destroy(s);
      return st;
    }
    if (!u->all) {
      u->all = s;
      continue;
    }
    st = satf_strand_set_concat(u->all, s, &both, err);
    satf_strand_set_destroy(u->all);
    satf_strand_set_destroy(s);
    u->all = both;
    if (st != SATF_OK)
      return st;
  }
  u->r->n_strands = satf_strand_set_count(u->all);
  u->r->n_points = satf_strand_set_point_count(u->all);
  return SATF_OK;
}

static int cmp_float(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

/* Rebuilds u->all with every point (and thickness) multiplied by k, and,
 * where width is given (one per strand), that width as every point's
 * thickness. */
static satf_status rebuild_strands(run *u, double k, const float *width,
                                   satf_error *err) {
  const satf_strand_set *s = u->all;
  int n = satf_strand_set_count(s);
  size_t np = satf_strand_set_point_count(s);
  int *counts = malloc((size_t)n * sizeof(int));
  float *pts = malloc(3 * np * sizeof(float));
  int thick = width || satf_strand_set_thickness(s, 0) != NULL;
  float *th = thick ? malloc(np * sizeof(float)) : NULL;
  satf_status st = SATF_OK;
  if (!counts || !pts || (thick && !th))
    st = satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  /* no strand wider than the hair: a cyHair file in tiny units keeps its
   * header's default thickness of 1, which x1e40 would overflow */
  float lo[3], hi[3];
  satf_strand_set_bounds(s, lo, hi);
  double widest = 0.0;
  for (int c = 0; c < 3; c++)
    widest += ((double)hi[c] - lo[c]) * ((double)hi[c] - lo[c]);
  widest = sqrt(widest) * k;
  for (int i = 0, at = 0; i < n && st == SATF_OK; i++) {
    const float *p = satf_strand_set_strand(s, i, &counts[i]);
    const float *t = satf_strand_set_thickness(s, i);
    for (int j = 0; j < counts[i]; j++, at++) {
      for (int c = 0; c < 3; c++)
        pts[3 * at + c] = (float)(p[3 * j + c] * k);
      if (thick)
        th[at] = (float)fmin((width ? width[i] : t[j]) * k, widest);
    }
  }
  satf_strand_set *rebuilt = NULL;
  if (st == SATF_OK)
    st = satf_strand_set_create(n, counts, pts, th, &rebuilt, err);
  if (st == SATF_OK) {
    satf_strand_set_destroy(u->all);
    u->all = rebuilt;
  }
  free(counts);
  free(pts);
  free(th);
  return st;
}

/* Strands whose files give no thickness get a hair fibre's,
 * SATF_IMPORT_FIBRE_WIDTH of the hair's bounding-box diagonal (or
 * --strand-width's), before clustering: the strand file, the reference,
 * lone strands and the density then assume the same strands at every
 * --quality. Real hair is some thousand fibres across the hairstyle; a
 * width from the spacing of the file's strands drew a few thousand guides
 * as ribbons 3 to 14 times a fibre's width (the shared ponytail: 0.625
 * units against 0.18). A sequence keeps its keyframes' own widths. */
static satf_status default_thickness(run *u, satf_error *err) {
  int n = satf_strand_set_count(u->all);
  if (n == 0 || u->o->sequence || satf_strand_set_thickness(u->all, 0))
    return SATF_OK;
  float *w = malloc((size_t)n * sizeof *w);
  if (!w)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  u->r->strand_width_given = u->o->strand_width > 0.0;
  float lo[3], hi[3];
  satf_strand_set_bounds(u->all, lo, hi);
  double diag = 0.0;
  for (int c = 0; c < 3; c++)
    diag += ((double)hi[c] - lo[c]) * ((double)hi[c] - lo[c]);
  diag = sqrt(diag);
  /* the user's, in the input's units; a hairstyle of one point (no
   * diagonal) keeps a width of 1 */
  float width =
      (float)(u->o->strand_width > 0.0 ? u->o->strand_width * u->r->scale
              : diag > 0.0             ? SATF_IMPORT_FIBRE_WIDTH * diag
                                       : 1.0);
  for (int i = 0; i < n; i++)
    w[i] = width;
  u->r->spacing_width[0] = u->r->spacing_width[1] = u->r->spacing_width[2] =
      width;
  satf_status st = rebuild_strands(u, 1.0, w, err);
  free(w);
  return st;
}

/* Hair in tiny units (spanning under IMPORT_MIN_SPAN: fitting and voxels
 * would run into the scene's and the grid's resolution) or huge ones
 * (coordinates over IMPORT_MAX_COORD, a tenth of the scene limit, leaving
 * room for the camera) is rescaled by a power of ten so that it spans 1 to
 * 10 units. With a mesh or a sequence the other files would no longer
 * match, so those are refused instead. */
#define IMPORT_MIN_SPAN 1e-2
#define IMPORT_MAX_COORD (0.1 * SATF_SCENE_MAX_COORD)
static satf_status fit_units(run *u, satf_error *err) {
  const satf_import_options *o = u->o;
  float lo[3], hi[3];
  satf_strand_set_bounds(u->all, lo, hi);
  double span = 0.0, far = 0.0;
  for (int c = 0; c < 3; c++) {
    span += ((double)hi[c] - lo[c]) * ((double)hi[c] - lo[c]);
    far = fmax(far, fmax(fabs((double)lo[c]), fabs((double)hi[c])));
  }
  span = sqrt(span);
  u->r->scale = 1.0;
  if ((span >= IMPORT_MIN_SPAN && far <= IMPORT_MAX_COORD) || !(span > 0.0))
    return SATF_OK;
  const char *more = o->n_inputs > 1 ? " (and the other inputs)" : "";
  if (o->mesh || o->sequence)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s%s: the hair spans %g units with coordinates up "
                          "to %g, outside what a scene holds (spans of at "
                          "least %g, coordinates up to %g), and with %s it "
                          "cannot be rescaled: scale the strands",
                          o->inputs[0], more, span, far, IMPORT_MIN_SPAN,
                          IMPORT_MAX_COORD, o->mesh ? "--mesh" : "a sequence");
  double k = pow(10.0, -floor(log10(span)));
  if (far * k > IMPORT_MAX_COORD)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s%s: the hair spans %g units but lies %g from "
                          "the origin: no scale brings it within the scene "
                          "limits (coordinates up to %g, a tenth of the "
                          "scene's %g, leave the camera room)",
                          o->inputs[0], more, span, far, IMPORT_MAX_COORD,
                          SATF_SCENE_MAX_COORD);
  u->r->scale = k;
  return rebuild_strands(u, k, NULL, err);
}

static satf_status cluster(run *u, satf_error *err) {
  const satf_import_options *o = u->o;
  satf_import_cluster_params cp = satf_import_cluster_params_default();
  cp.clusters = (int)o->clusters;
  cp.seed = o->seed;
  cp.threads = (int)o->threads;
  u->labels = malloc((size_t)u->r->n_strands * sizeof(int));
  satf_progress bar;
  satf_status st;
  if (o->clusters == 0 && u->labels) { /* adaptive: fitted as it goes */
    u->fp = satf_import_fit_params_default();
    u->fp.n_ctrl = (int)o->control;
    u->fp.samples = u->fp.n_ctrl * 4 > 32 ? u->fp.n_ctrl * 4 : 32;
    u->fp.min_radius = 0.5f * satf_strand_set_root_spacing(u->all);
    u->rp = satf_import_refine_params_for(u->all, o->quality, o->tolerance);
    u->rp.threads = (int)o->threads;
    /* a sequence's keyframes are re-fitted with fp's count: every cluster
     * keeps it */
    if (u->rp.max_ctrl < u->fp.n_ctrl || o->sequence)
      u->rp.max_ctrl = u->fp.n_ctrl;
    satf_progress_begin(&bar, stderr, "clustering", "clusters fit", 1,
                        o->quiet);
    st =
        satf_import_refine(u->all, &cp, &u->rp, &u->fp, u->labels,
                           &u->r->n_clusters, &u->fits, progress_cb, &bar, err);
    satf_progress_end(&bar);
    return st;
  }
  satf_progress_begin(&bar, stderr, "clustering", "iterations", 1, o->quiet);
  st = u->labels ? satf_import_kmeans(u->all, &cp, u->labels, &u->r->n_clusters,
                                      &u->r->rms, progress_cb, &bar, err)
                 : satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  satf_progress_end(&bar);
  return st;
}

/* Each cluster's curl (import_curl.c), after either clustering. */
static satf_status fits_curl(run *u, satf_error *err) {
  if (satf_import_fits_curl(u->all, u->labels, u->fits, u->r->n_clusters,
                            (int)u->o->threads))
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory",
                          u->o->inputs[0]);
  return SATF_OK;
}

static satf_status fit(run *u, satf_error *err) {
  const satf_import_options *o = u->o;
  int n = u->r->n_clusters;
  if (u->fits) /* the adaptive clustering fitted them */
    return fits_curl(u, err);
  u->fits = calloc((size_t)n, sizeof *u->fits);
  u->fp = satf_import_fit_params_default();
  u->fp.n_ctrl = (int)o->control;
  u->fp.samples = u->fp.n_ctrl * 4 > 32 ? u->fp.n_ctrl * 4 : 32;
  u->fp.min_radius = 0.5f * satf_strand_set_root_spacing(u->all);
  satf_progress bar;
  satf_progress_begin(&bar, stderr, "fitting", "clusters", 1, o->quiet);
  satf_error why;
  satf_status st =
      u->fits
          ? satf_import_fit_all(u->all, u->labels, n, &u->fp, (int)o->threads,
                                u->fits, progress_cb, &bar, &why)
          : satf_error_set(&why, SATF_ERR_NOMEM, "out of memory");
  satf_progress_end(&bar);
  if (st != SATF_OK)
    return satf_error_set(err, st, "%s%s: fitting failed: %s", o->inputs[0],
                          o->n_inputs > 1 ? " (and the other inputs)" : "",
                          why.message);
  return fits_curl(u, err);
}

/* The VDB voxel: a sixth of the median cluster radius, no finer than 1/512
 * of the hairstyle and coarse enough for the widest strand's footprint. */
static float default_voxel(const satf_import_fit *fits, int n, float diag) {
  float *r = malloc((size_t)n * sizeof(float));
  float med = diag / 100.0f, widest = 0.0f;
  if (r) {
    for (int c = 0; c < n; c++)
      r[c] = fits[c].radius;
    qsort(r, (size_t)n, sizeof(float), cmp_float);
    med = r[n / 2];
    free(r);
  }
  for (int c = 0; c < n; c++) {
    float s = satf_import_world_sigma(&fits[c]);
    widest = s > widest ? s : widest;
  }
  float v = med / 6.0f;
  v = v > diag / 512.0f ? v : diag / 512.0f;
  v = v > widest / 20.0f ? v : widest / 20.0f;
  return v;
}

/* Writes the density grid to path (a satf_import_side writer). */
static satf_status density_grid(const char *path, void *ctx, satf_error *err) {
  run *u = ctx;
  const satf_import_options *o = u->o;
  float lo[3], hi[3];
  satf_strand_set_bounds(u->all, lo, hi);
  float diag = sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                     (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                     (hi[2] - lo[2]) * (hi[2] - lo[2]));
  u->r->voxel = o->voxel > 0.0 ? (float)o->voxel
                               : default_voxel(u->fits, u->r->n_clusters, diag);
  satf_vdb_builder *b = NULL;
  satf_progress bar;
  satf_progress_begin(&bar, stderr, "density", "strands", 1, o->quiet);
  satf_status st = satf_import_build_vdb(
      u->all, u->labels, u->fits, u->r->voxel, &b, progress_cb, &bar, err);
  satf_progress_end(&bar);
  if (st == SATF_OK)
    st = satf_vdb_builder_write(b, path, "density", err);
  if (st == SATF_OK) {
    satf_vdb_grid *g = NULL;
    if (satf_vdb_builder_to_grid(b, &g, err) == SATF_OK)
      u->r->vdb_mass = satf_vdb_total_mass(g);
    satf_vdb_grid_destroy(g);
  }
  satf_vdb_builder_destroy(b);
  return st;
}

/* The material the command line gives (each value < 0: the default). */
static void apply_material(const satf_import_options *o,
                           satf_scene_material *m) {
  if (o->shading >= 0 && o->shading < SATF_MATERIAL_MODEL_COUNT)
    m->model = (satf_material_model)o->shading;
  const double given[4] = {o->melanin, o->redness, o->roughness,
                           o->radial_roughness};
  float *field[4] = {&m->melanin, &m->redness, &m->roughness,
                     &m->radial_roughness};
  for (int k = 0; k < 4; k++)
    if (given[k] >= 0.0)
      *field[k] = (float)given[k];
}

/* The physical shading's densities at scale 1. satf_import_density_scale
 * matches the kk database's records (the Phong trace's extinction, one
 * record's depth per layer) to opaque strands; the fibre records are
 * traced from circular fibres and were measured against Cycles without it.
 * With it the ponytail back-lit fell from 0.89 to 0.75 of Cycles'
 * luminance (front-lit 0.84 -> 0.86; the bands asked were 0.8-1.25
 * and 0.85-1.15). */
static void unit_density_scale(satf_scene *scene) {
  for (int m = 0; m < scene->n_macro_clusters; m++)
    scene->macro_clusters[m].prototype.density.scale = 1.0f;
}

/* The scene, with keys for a sequence. */
static satf_status build_scene(run *u, satf_scene **scene, satf_error *err) {
  const satf_import_options *o = u->o;
  char desc[512];
  snprintf(desc, sizeof desc,
           "imported by satf-import from %s%s: %d strands in %d clusters "
           "(%d macro-clusters)",
           o->inputs[0], o->n_inputs > 1 ? " and more" : "", u->r->n_strands,
           u->r->n_clusters, u->macro.n_macro);
  /* The grid's published name is known once it is written (publish). */
  /* the camera frames the strands, grown by their widest half-width */
  float lo[3], hi[3], grow = 0.0f;
  satf_strand_set_bounds(u->all, lo, hi);
  for (int i = 0; satf_strand_set_thickness(u->all, 0) &&
                  i < satf_strand_set_count(u->all);
       i++) {
    const float *th = satf_strand_set_thickness(u->all, i);
    for (int k = 0; k < satf_strand_set_points(u->all, i); k++)
      grow = fmaxf(grow, 0.5f * th[k]);
  }
  for (int c = 0; c < 3; c++) {
    lo[c] -= grow;
    hi[c] += grow;
  }
  satf_import_scene_options so = {
      o->vdb, "density", o->database ? u->database : NULL, desc, 0,
      0,      o->seed,   o->mesh ? u->mesh_path : NULL,    lo,   hi};
  satf_status st = satf_import_scene_build(u->fits, u->r->n_clusters, &u->macro,
                                           &so, o->output, scene, err);
  if (st == SATF_OK)
    apply_material(o, &(*scene)->material);
  if (st == SATF_OK && (*scene)->material.model == SATF_MATERIAL_PHYSICAL)
    unit_density_scale(*scene);
  if (st == SATF_OK && o->sequence)
    st = satf_import_sequence_keys(*scene, o, u->labels, u->r->n_strands,
                                   &u->fp, &u->macro, err);
  if (st == SATF_OK && o->mesh && (*scene)->n_meshes > 0)
    memcpy((*scene)->meshes[(*scene)->n_meshes - 1].m, u->mesh_m,
           sizeof u->mesh_m);
  return st;
}

/* The scene goes through the checks satf_scene_load makes (the text it
 * would be written as, parsed back), so satf-import never writes a scene
 * the renderer refuses: fitted values past the scene limits (a twist over
 * 1e4 rad from a tightly wound strand, coordinates past 1e6) are caught
 * here, before any file is written. */
static satf_status check_scene(run *u, const satf_scene *scene,
                               satf_error *err) {
  const satf_import_options *o = u->o;
  char *json = NULL;
  satf_scene *back = NULL;
  satf_error why;
  satf_status st = satf_scene_to_json(scene, NULL, &json, &why);
  if (st == SATF_OK)
    st = satf_scene_parse(json, strlen(json), o->output, &back, &why);
  free(json);
  satf_scene_destroy(back);
  if (st != SATF_OK)
    return satf_error_set(err, st,
                          "%s%s: the scene made from it breaks the scene "
                          "limits, so the renderer would refuse it (nothing "
                          "written): %s",
                          o->inputs[0],
                          o->n_inputs > 1 ? " (and the other inputs)" : "",
                          why.message);
  return SATF_OK;
}

/* Fit quality and density totals for the summary. */
static void tally(run *u) {
  satf_import_result *r = u->r;
  for (int c = 0; c < r->n_clusters; c++) {
    r->points += u->fits[c].points;
    r->inside += u->fits[c].inside;
    r->distance_sum += u->fits[c].distance_sum;
    r->width_sum += u->fits[c].strand_width;
    r->gradient += u->fits[c].layout == SATF_SCENE_LAYOUT_GRADIENT;
  }
  satf_import_fit_stats_compute(u->fits, r->n_clusters,
                                u->o->clusters == 0 ? &u->rp : NULL, &r->fit);
  r->n_macro = u->macro.n_macro;
  r->bytes_separate = u->macro.bytes_separate;
  r->bytes_shared = u->macro.bytes_shared;
}

/* Whether some strand root lies in the mesh's bounds grown by a tenth of
 * their diagonal: a head and the hair on it always meet; a head far from
 * every root was probably placed in other units or axes. */
static int roots_meet_mesh(const run *u) {
  float grow = 0.0f;
  for (int c = 0; c < 3; c++)
    grow += (u->mesh_hi[c] - u->mesh_lo[c]) * (u->mesh_hi[c] - u->mesh_lo[c]);
  grow = 0.1f * sqrtf(grow);
  for (int i = 0; i < satf_strand_set_count(u->all); i++) {
    int n;
    const float *p = satf_strand_set_strand(u->all, i, &n);
    int in = 1;
    for (int c = 0; c < 3; c++)
      in &= p[c] >= u->mesh_lo[c] - grow && p[c] <= u->mesh_hi[c] + grow;
    if (in)
      return 1;
  }
  return 0;
}

/* Writes the strands (in scene coordinates) to path as cyHair. A file
 * without thickness (TressFX, PLY, .data) gets, per strand, the width its
 * cluster's density assumes (strand_width x radius, a diameter), so the
 * strand reference (satf-render --strands) draws what the clusters stand
 * for rather than the format's default of 1 unit whatever the scale.
 * Colours, where the file gave them, are written too. */
static satf_status write_strands(const char *path, void *ctx, satf_error *err) {
  const run *u = ctx;
  int n = satf_strand_set_count(u->all);
  if (n == 0 || satf_strand_set_thickness(u->all, 0) || !u->fits || !u->labels)
    return satf_hair_write(path, u->all, err);
  size_t points = satf_strand_set_point_count(u->all);
  int *counts = malloc((size_t)n * sizeof(int));
  float *xyz = malloc(3 * points * sizeof(float));
  float *th = malloc(points * sizeof(float));
  satf_status st = SATF_OK;
  if (!counts || !xyz || !th)
    st = satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  size_t at = 0;
  for (int i = 0; i < n && st == SATF_OK; i++) {
    const float *p = satf_strand_set_strand(u->all, i, &counts[i]);
    const satf_import_fit *f = &u->fits[u->labels[i]];
    float w = f->strand_width * f->radius;
    memcpy(xyz + 3 * at, p, 3 * (size_t)counts[i] * sizeof(float));
    for (int k = 0; k < counts[i]; k++)
      th[at + (size_t)k] = w > 0.0f ? w : 1.0f;
    at += (size_t)counts[i];
  }
  satf_strand_set *s = NULL;
  if (st == SATF_OK)
    st = satf_strand_set_create(n, counts, xyz, th, &s, err);
  /* the points' colours (an OBJ's), all strands in the same order */
  const float *rgb = n > 0 ? satf_strand_set_colour(u->all, 0) : NULL;
  if (st == SATF_OK && rgb)
    st = satf_strand_set_add_colour(s, rgb, err);
  if (st == SATF_OK)
    st = satf_hair_write(path, s, err);
  satf_strand_set_destroy(s);
  free(counts);
  free(xyz);
  free(th);
  return st;
}

/* A path given on the command line, made absolute against the working
 * directory (the scene names it relative to itself when written). */
static satf_status absolute_path(const char *flag, const char *path, char *out,
                                 satf_error *err) {
  char cwd[PATH_MAX];
  int n = path[0] == '/' ? snprintf(out, PATH_MAX, "%s", path)
          : getcwd(cwd, sizeof cwd)
              ? snprintf(out, PATH_MAX, "%s/%s", cwd, path)
              : -1;
  if (n < 0 || n >= PATH_MAX)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "%s %s: path is too long",
                          flag, path);
  return SATF_OK;
}

/* The base of the strands file: SCENE's name without .json, plus
 * ".strands.hair", beside it. */
static void strands_base(const char *scene, char *out, size_t size) {
  const char *slash = strrchr(scene, '/');
  const char *dot = strrchr(slash ? slash + 1 : scene, '.');
  size_t len = dot && dot != (slash ? slash + 1 : scene) ? (size_t)(dot - scene)
                                                         : strlen(scene);
  snprintf(out, size, "%.*s.strands.hair", (int)len, scene);
}

/* The side files (density grid, strands) and the scene, published as one
 * unit (satf_import_stage_side, satf_import_publish_scene). */
static satf_status publish(run *u, satf_scene *scene, satf_error *err) {
  const satf_import_options *o = u->o;
  satf_import_side sides[2];
  memset(sides, 0, sizeof sides);
  char hair_base[PATH_MAX];
  int n = 0;
  satf_status st = SATF_OK;
  if (o->vdb) {
    sides[n] =
        (satf_import_side){.base = o->vdb, .write = density_grid, .ctx = u};
    st = satf_import_stage_side(&sides[n++], err);
    snprintf(u->r->vdb_file, sizeof u->r->vdb_file, "%s", sides[0].published);
    for (int m = 0; st == SATF_OK && m < scene->n_macro_clusters; m++) {
      satf_scene_density *d = &scene->macro_clusters[m].prototype.density;
      char *copy = malloc(strlen(sides[0].published) + 1);
      if (!copy) {
        st = satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
        break;
      }
      strcpy(copy, sides[0].published);
      free(d->vdb_file);
      d->vdb_file = copy;
    }
  }
  u->r->t_vdb = satf_now_seconds() - u->t0;
  if (st == SATF_OK && !o->no_strands) {
    strands_base(o->output, hair_base, sizeof hair_base);
    sides[n] =
        (satf_import_side){.base = hair_base, .write = write_strands, .ctx = u};
    satf_import_side *h = &sides[n++];
    st = satf_import_stage_side(h, err);
    snprintf(u->r->strands_file, sizeof u->r->strands_file, "%s", h->published);
    free(scene->strands_file);
    scene->strands_file = NULL;
    if (st == SATF_OK &&
        !(scene->strands_file = malloc(strlen(h->published) + 1)))
      st = satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
    if (st == SATF_OK)
      strcpy(scene->strands_file, h->published);
  }
  if (st == SATF_OK)
    return satf_import_publish_scene(scene, o->output, sides, n, err);
  satf_import_discard_sides(sides, n); /* staged only: nothing names them */
  return st;
}

/* The folder an output goes into exists and takes new files: checked
 * before the work, which can take minutes, not after it. */
static satf_status check_output_dir(const char *flag, const char *path,
                                    satf_error *err) {
  char dir[PATH_MAX];
  const char *slash = strrchr(path, '/');
  snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - path) : 1,
           slash ? (slash == path ? "/" : path) : ".");
  if (access(dir, W_OK | X_OK) != 0)
    return satf_error_set(err, SATF_ERR_IO, "%s %s: cannot write into %s: %s",
                          flag, path, dir, strerror(errno));
  return SATF_OK;
}

static satf_status steps(run *u, satf_error *err) {
  satf_import_result *r = u->r;
  satf_status st = SATF_OK;
  if ((st = check_output_dir("-o", u->o->output, err)) != SATF_OK ||
      (u->o->vdb &&
       (st = check_output_dir("--vdb", u->o->vdb, err)) != SATF_OK) ||
      (u->o->database && (st = absolute_path("--db", u->o->database,
                                             u->database, err)) != SATF_OK) ||
      (u->o->mesh && (st = check_mesh(u, err)) != SATF_OK) ||
      (st = read_inputs(u, err)) != SATF_OK ||
      (st = fit_units(u, err)) != SATF_OK ||
      (st = default_thickness(u, err)) != SATF_OK)
    return st;
  r->t_read = satf_now_seconds() - u->t0;
  r->mb_read = satf_peak_memory_mb();
  if (u->o->mesh)
    r->mesh_apart = !roots_meet_mesh(u);
  if ((st = cluster(u, err)) != SATF_OK)
    return st;
  r->t_cluster = satf_now_seconds() - u->t0;
  r->mb_cluster = satf_peak_memory_mb();
  if ((st = fit(u, err)) != SATF_OK)
    return st;
  r->t_fit = satf_now_seconds() - u->t0;
  if (u->o->fit_report &&
      (st = satf_import_write_fit_report(u->o->fit_report, u->fits,
                                         r->n_clusters, err)) != SATF_OK)
    return st;
  satf_progress bar;
  satf_progress_begin(&bar, stderr, "macro-clusters", "clusters", 1,
                      u->o->quiet);
  st = satf_import_find_macro(u->fits, r->n_clusters, (float)u->o->macro_tol,
                              progress_cb, &bar, &u->macro, err);
  satf_progress_end(&bar);
  if (st != SATF_OK)
    return st;
  u->have_macro = 1;
  r->t_macro = satf_now_seconds() - u->t0;
  satf_scene *scene = NULL;
  if ((st = build_scene(u, &scene, err)) == SATF_OK &&
      (st = check_scene(u, scene, err)) == SATF_OK) {
    r->t_check = r->t_vdb0 = satf_now_seconds() - u->t0;
    r->mb_check = satf_peak_memory_mb();
    st = publish(u, scene, err);
  }
  satf_scene_destroy(scene);
  if (st != SATF_OK)
    return st;
  r->t_end = satf_now_seconds() - u->t0;
  tally(u);
  r->peak_mb = satf_peak_memory_mb();
  return SATF_OK;
}

satf_status satf_import_run(const satf_import_options *o,
                            satf_import_result *result, satf_error *err) {
  run u;
  memset(&u, 0, sizeof u);
  memset(result, 0, sizeof *result);
  u.o = o;
  u.r = result;
  u.t0 = satf_now_seconds();
  satf_status st = steps(&u, err);
  if (u.have_macro)
    satf_import_macro_free(&u.macro);
  for (int c = 0; u.fits && c < result->n_clusters; c++)
    satf_import_fit_free(&u.fits[c]);
  free(u.fits);
  free(u.labels);
  satf_strand_set_destroy(u.all);
  return st;
}

void satf_import_print_summary(FILE *out, const char *prog,
                               const satf_import_options *o,
                               const satf_import_result *r) {
  char b1[32], b2[32];
  fprintf(out, "%s: %s\n", prog, o->output);
  fprintf(out, "  strands          %d (%zu points, from %d file%s)\n",
          r->n_strands, r->n_points, o->n_inputs, o->n_inputs > 1 ? "s" : "");
  if (r->dropped_strands || r->merged_points)
    fprintf(out,
            "  dropped          %d strand%s of zero length (all points "
            "coincide), %zu coincident point%s merged\n",
            r->dropped_strands, r->dropped_strands == 1 ? "" : "s",
            r->merged_points, r->merged_points == 1 ? "" : "s");
  if (o->clusters)
    fprintf(out, "  clusters         %d (as asked; k-means RMS %.4g)\n",
            r->n_clusters, r->rms);
  else
    fprintf(out,
            "  clusters         %d (adaptive, --quality %s: split until each "
            "fits its strands)\n",
            r->n_clusters,
            o->quality == SATF_IMPORT_QUALITY_DRAFT  ? "draft"
            : o->quality == SATF_IMPORT_QUALITY_HIGH ? "high"
                                                     : "default");
  fprintf(out,
          "  macro-clusters   %d (tolerance %g): %s -> %s of cluster "
          "parameters\n",
          r->n_macro, o->macro_tol,
          satf_format_bytes((double)r->bytes_separate, b1, sizeof b1),
          satf_format_bytes((double)r->bytes_shared, b2, sizeof b2));
  satf_import_fit_stats_print(out, prog, &r->fit);
  fprintf(out,
          "  density          mean strand width %.3g cluster radii; %d of "
          "%d clusters \"gradient\", the rest \"uniform\"\n",
          r->width_sum / r->n_clusters, r->gradient, r->n_clusters);
  if (r->follow >= 0 && o->follow >= 0)
    fprintf(out,
            "  followers        %d per TressFX guide (--follow's): %d "
            "guides drawn as %d fibres\n",
            r->follow, r->guides, r->guides * (r->follow + 1));
  else if (r->follow >= 0)
    fprintf(out,
            "  followers        %d per TressFX guide (the header's "
            "numFollowStrandsPerGuide, or TressFX's default of %d where it "
            "names none; --follow N sets another): %d guides drawn as %d "
            "fibres\n",
            r->follow, SATF_IMPORT_TFX_FOLLOW, r->guides,
            r->guides * (r->follow + 1));
  if (r->spacing_width[1] > 0.0f && r->strand_width_given)
    fprintf(out,
            "  strand width     %.3g: the files give none, so "
            "--strand-width's\n",
            (double)r->spacing_width[1]);
  else if (r->spacing_width[1] > 0.0f)
    fprintf(out,
            "  strand width     %.3g: the files give none, so a hair "
            "fibre's, %g of the hair's bounding-box diagonal "
            "(--strand-width sets one)\n",
            (double)r->spacing_width[1], SATF_IMPORT_FIBRE_WIDTH);
  if (r->scale != 1.0)
    fprintf(out,
            "  scale            x%g (the hair's units were too %s for a "
            "scene: rescaled to span 1 to 10 units)\n",
            r->scale, r->scale > 1.0 ? "small" : "large");
  if (o->vdb)
    fprintf(out, "  vdb              %s (voxel %.4g, mass %.4g)\n",
            r->vdb_file[0] ? r->vdb_file : o->vdb, (double)r->voxel,
            r->vdb_mass);
  if (r->strands_file[0])
    fprintf(out, "  strands file     %s\n", r->strands_file);
  if (o->database)
    fprintf(out, "  database         %s\n", o->database);
  else
    fprintf(out, "  database         none named (render with --db DB.exr, "
                 "or import with --db)\n");
  fprintf(out,
          "  time             %.2f s (read %.2f, cluster %.2f, fit %.2f, "
          "macro %.2f, scene check %.2f, vdb %.2f, strands and scene "
          "writing %.2f)\n"
          "  peak memory      %.0f MB (%.0f after reading, %.0f after "
          "clustering, %.0f after the scene's check)\n",
          r->t_end, r->t_read, r->t_cluster - r->t_read,
          r->t_fit - r->t_cluster, r->t_macro - r->t_fit,
          r->t_check - r->t_macro, r->t_vdb - r->t_vdb0, r->t_end - r->t_vdb,
          r->peak_mb, r->mb_read, r->mb_cluster, r->mb_check);
  if (r->mesh_apart)
    fprintf(out,
            "%s: warning: no strand root meets the mesh %s (its bounds "
            "after --mesh-transform); place it with --mesh-transform%s\n",
            prog, o->mesh,
            o->up_z ? "" : ", or give --up z if the files are Z-up");
}
