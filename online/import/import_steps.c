/* import_steps.c - the steps of an import that satf-import and the
 * sequence import share: its options, reading a strand file whatever its
 * format, and fitting every cluster in parallel. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "import_internal.h"
#include "import_prepare.h"
#include "satf/common.h"
#include "strands_formats.h"

satf_import_options satf_import_options_default(void) {
  satf_import_options o;
  memset(&o, 0, sizeof o);
  o.follow = -1;
  o.follow_radius = -1.0;
  o.tip_separation = 0.5;
  o.control = 8;
  o.macro_tol = 0.05;
  o.seed = 1;
  o.memory_budget = SATF_IMPORT_DEFAULT_BUDGET;
  o.mesh_axis[1] = o.hair_axis[1] = 1.0;
  o.mesh_scale[0] = o.mesh_scale[1] = o.mesh_scale[2] = 1.0;
  o.hair_scale[0] = o.hair_scale[1] = o.hair_scale[2] = 1.0;
  o.melanin = o.redness = o.roughness = o.radial_roughness = -1.0;
  o.shading = -1;
  return o;
}

satf_status satf_import_check_budget(const satf_import_options *o,
                                     const char *what, size_t points,
                                     satf_error *err) {
  double budget =
      o->memory_budget > 0.0 ? o->memory_budget : SATF_IMPORT_DEFAULT_BUDGET;
  double need = (double)points * SATF_IMPORT_BYTES_PER_POINT;
  if (need <= budget)
    return SATF_OK;
  char b1[32], b2[32];
  return satf_error_set(
      err, SATF_ERR_ARGUMENT,
      "%s: %zu strand points would need about %s to import (%d bytes a "
      "point), over the memory budget of %s: import fewer strands, or raise "
      "it with --memory-budget GB",
      what, points, satf_format_bytes(need, b1, sizeof b1),
      SATF_IMPORT_BYTES_PER_POINT, satf_format_bytes(budget, b2, sizeof b2));
}

/* Follow strands are refused before they are made when the points they
 * would add break the budget; the message says how many would fit. */
static satf_status check_follow(const satf_import_options *o, const char *path,
                                const satf_strand_set *guides, int count,
                                int from_header, satf_error *err) {
  size_t guide_points = satf_strand_set_point_count(guides);
  size_t points = guide_points * (size_t)(count + 1);
  satf_error why;
  if (satf_import_check_budget(o, path, points, &why) == SATF_OK)
    return SATF_OK;
  double budget =
      o->memory_budget > 0.0 ? o->memory_budget : SATF_IMPORT_DEFAULT_BUDGET;
  double fit = budget / SATF_IMPORT_BYTES_PER_POINT / (double)guide_points;
  long most = fit >= 1.0 ? (long)fit - 1 : -1;
  char b1[32], b2[32];
  if (most < 0)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "%s", why.message);
  return satf_error_set(
      err, SATF_ERR_ARGUMENT,
      "%s: %s %d follow strands per guide: %d guides of %zu points become "
      "%zu points, about %s to import, over the memory budget of %s; at most "
      "%ld followers per guide fit (--follow %ld), or raise the budget with "
      "--memory-budget GB",
      path, from_header ? "its header asks for" : "--follow asks for", count,
      satf_strand_set_count(guides), guide_points, points,
      satf_format_bytes((double)points * SATF_IMPORT_BYTES_PER_POINT, b1,
                        sizeof b1),
      satf_format_bytes(budget, b2, sizeof b2), most, most);
}

static void follow_progress(void *ctx, size_t done, size_t total) {
  satf_progress_update(ctx, done, total);
}

int satf_import_follow_count(const satf_import_options *o, int header_follow) {
  return o->follow >= 0      ? (int)o->follow
         : header_follow > 0 ? header_follow
                             : SATF_IMPORT_TFX_FOLLOW;
}

/* Coordinates past SATF_IMPORT_MAX_INPUT_COORD are refused, naming the
 * first such point: no unit puts a hair there (a metre in nanometres is
 * 1e9), the squared distances the fit sums overflow a float from about
 * 1e19, and such values are what a damaged or misread file holds. Tiny
 * units (1e-40) stay: the import rescales them by a power of ten. */
static satf_status check_coordinates(const satf_strand_set *s, const char *path,
                                     satf_error *err) {
  for (int i = 0; i < satf_strand_set_count(s); i++) {
    int n;
    const float *p = satf_strand_set_strand(s, i, &n);
    for (int j = 0; j < 3 * n; j++)
      if (!(fabsf(p[j]) <= SATF_IMPORT_MAX_INPUT_COORD))
        return satf_error_set(
            err, SATF_ERR_CORRUPT,
            "%s: strand %d point %d has the coordinate %g, beyond the %g "
            "an input may hold (a damaged file, or units no hair is "
            "measured in: scale the strands)",
            path, i, j / 3, (double)p[j], SATF_IMPORT_MAX_INPUT_COORD);
  }
  return SATF_OK;
}

/* The parser of format f on the file's bytes; TressFX guides get their
 * follow strands as o asks (*followers: how many per guide). */
static satf_status parse_as(satf_strands_format f, const void *data,
                            size_t size, const char *path,
                            const satf_import_options *o, satf_strand_set **out,
                            int *followers, satf_error *err) {
  if (f != SATF_STRANDS_TFX) {
    satf_status st =
        f == SATF_STRANDS_HAIR  ? satf_hair_parse(data, size, path, out, err)
        : f == SATF_STRANDS_PLY ? satf_ply_parse(data, size, path, out, err)
        : f == SATF_STRANDS_USC ? satf_usc_parse(data, size, path, out, err)
                                : satf_obj_parse(data, size, path, out, err);
    if (st == SATF_OK && (st = check_coordinates(*out, path, err)) != SATF_OK) {
      satf_strand_set_destroy(*out);
      *out = NULL;
    }
    return st;
  }
  satf_tfx_info info;
  satf_strand_set *guides;
  satf_status st = satf_tfx_parse(data, size, path, &info, &guides, err);
  if (st == SATF_OK && (st = check_coordinates(guides, path, err)) != SATF_OK)
    satf_strand_set_destroy(guides);
  if (st != SATF_OK)
    return st;
  satf_follow_params fp;
  fp.count = satf_import_follow_count(o, info.follow_per_guide);
  *followers = fp.count;
  fp.radius = o->follow_radius >= 0.0 ? (float)o->follow_radius
                                      : satf_strand_set_root_spacing(guides);
  fp.tip_separation = (float)o->tip_separation;
  fp.seed = o->seed;
  if (fp.count == 0) {
    *out = guides;
    return SATF_OK;
  }
  st = check_follow(o, path, guides, fp.count, o->follow < 0, err);
  if (st == SATF_OK) {
    satf_progress bar;
    satf_progress_begin(&bar, stderr, "follow strands", "guides", 1, o->quiet);
    st = satf_strand_set_add_follow_progress(guides, &fp, follow_progress, &bar,
                                             out, err);
    satf_progress_end(&bar);
  }
  satf_strand_set_destroy(guides);
  return st;
}

static const char *extension_of(satf_strands_format f) {
  return f == SATF_STRANDS_HAIR  ? ".hair"
         : f == SATF_STRANDS_PLY ? ".ply"
         : f == SATF_STRANDS_USC ? ".data"
         : f == SATF_STRANDS_OBJ ? ".obj"
                                 : ".tfx";
}

/* The format is what the bytes say; the name only decides when they say
 * nothing (a .tfx then goes to its parser, which says what is wrong). A
 * name that promises another format than the bytes is refused, naming
 * both; bytes and a name that say nothing are refused with the formats
 * satf reads (never read as TressFX, whose version would be any float). */
satf_status satf_import_read_strands(const char *path,
                                     const satf_import_options *o,
                                     satf_strand_set **out, satf_error *err) {
  int followers;
  return satf_import_read_strands_followed(path, o, out, &followers, err);
}

satf_status satf_import_read_strands_followed(const char *path,
                                              const satf_import_options *o,
                                              satf_strand_set **out,
                                              int *followers, satf_error *err) {
  *out = NULL;
  *followers = -1;
  void *data;
  size_t size;
  satf_status st =
      satf_read_file(path, SATF_STRANDS_MAX_FILE_BYTES, &data, &size, err);
  if (st != SATF_OK)
    return st;
  satf_strands_format named = satf_strands_format_of_name(path);
  satf_strands_format is = satf_strands_detect(data, size);
  if (is != SATF_STRANDS_UNKNOWN && named != SATF_STRANDS_UNKNOWN &&
      is != named)
    st = satf_error_set(err, SATF_ERR_FORMAT,
                        "%s: this is a %s file, not %s (rename it to end in "
                        "%s)",
                        path, satf_strands_format_name(is),
                        satf_strands_format_name(named), extension_of(is));
  else if (is == SATF_STRANDS_UNKNOWN && named == SATF_STRANDS_UNKNOWN)
    st = satf_error_set(
        err, SATF_ERR_FORMAT,
        "%s: unrecognised format; satf reads " STRANDS_FORMATS_READ, path);
  else
    st = parse_as(is != SATF_STRANDS_UNKNOWN ? is : named, data, size, path, o,
                  out, followers, err);
  free(data);
  float m[16];
  int dropped;
  size_t merged;
  if (st == SATF_OK && import_hair_matrix(o, m))
    st = import_prepare_strands(out, m, 0, path, &dropped, &merged, err);
  if (st != SATF_OK) {
    satf_strand_set_destroy(*out);
    *out = NULL;
  }
  return st;
}

typedef struct fit_job {
  const satf_strand_set *strands;
  const int *labels;
  satf_import_fit *fits;
  const satf_import_fit_params *fp;
  satf_error *errs;
  satf_import_progress_fn progress;
  void *progress_ctx;
} fit_job;

/* Fits cluster c and estimates its density parameters. */
static int fit_one(void *vctx, size_t c, int thread) {
  (void)thread;
  fit_job *j = vctx;
  int *members, n;
  satf_error *err = &j->errs[c];
  int n_strands = satf_strand_set_count(j->strands);
  if (satf_import_members(j->labels, n_strands, (int)c, &members, &n, err))
    return 1;
  satf_status st =
      satf_import_fit_cluster(j->strands, members, n, j->fp, &j->fits[c], err);
  satf_cluster *cl = NULL;
  if (st == SATF_OK)
    st = satf_import_fit_cluster_create(&j->fits[c], &cl, err);
  satf_import_projection proj;
  if (st == SATF_OK)
    st = satf_import_project(j->strands, members, n, cl, &proj, err);
  if (st == SATF_OK) {
    satf_import_estimate_density(&proj, &j->fits[c]);
    satf_import_width_from_thickness(j->strands, members, n, &j->fits[c]);
    satf_import_projection_free(&proj);
  }
  satf_cluster_destroy(cl);
  free(members);
  return st != SATF_OK;
}

static void progress_cb(void *ctx, size_t done, size_t total) {
  fit_job *j = ctx;
  j->progress(j->progress_ctx, done, total);
}

satf_status satf_import_fit_all(const satf_strand_set *s, const int *labels,
                                int n_clusters, const satf_import_fit_params *p,
                                int threads, satf_import_fit *fits,
                                satf_import_progress_fn progress,
                                void *progress_ctx, satf_error *err) {
  satf_error *errs = calloc((size_t)n_clusters, sizeof *errs);
  if (!errs)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  fit_job job = {s, labels, fits, p, errs, progress, progress_ctx};
  satf_status st = SATF_OK;
  if (satf_parallel_for((size_t)n_clusters, threads, fit_one, &job,
                        progress ? progress_cb : NULL, &job) != 0) {
    const char *why = "out of memory";
    for (int c = 0; c < n_clusters; c++)
      if (errs[c].message[0]) {
        why = errs[c].message;
        break;
      }
    st = satf_error_set(err, SATF_ERR_FORMAT, "%s", why);
  }
  free(errs);
  return st;
}
