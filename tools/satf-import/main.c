/* satf-import - turns strand hair files (cyHair .hair, TressFX .tfx) into a
 * satf scene: clusters, fitted generalized cylinders, macro-clusters and
 * density (SATF sec. 3.1-3.3), optionally with a world-space OpenVDB
 * density grid. */
#define _XOPEN_SOURCE 700
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include <cjson/cJSON.h>

#include "satf/common.h"
#include "satf/import.h"
#include "satf/geometry.h"

static const char *PROG = "satf-import";

static void usage(FILE *out) {
  fprintf(
      out,
      "usage: %s INPUT... -o SCENE.json [options]\n"
      "\n"
      "Imports strand hair (cyHair .hair, TressFX 3.x/4.x .tfx; several "
      "files\n"
      "go into one scene) as SATF clusters: k-means on the strands, a\n"
      "generalized cylinder fitted to each cluster, macro-clusters for\n"
      "clusters that match after a similarity transform, and density.\n"
      "\n"
      "options:\n"
      "  -o, --output PATH      scene file to write (required)\n"
      "  --clusters N           cluster count (default: chosen from the "
      "data)\n"
      "  --vdb PATH             also write the density as an OpenVDB "
      "FloatGrid\n"
      "                         \"density\" and make the scene use it\n"
      "  --voxel SIZE           VDB voxel size (default: from the "
      "clusters)\n"
      "  --follow N             TressFX follow strands per guide "
      "(default: the\n"
      "                         file's header)\n"
      "  --follow-radius R      their root offset radius (default: the "
      "guides'\n"
      "                         mean root spacing)\n"
      "  --tip-separation F     followers spread (1 + F) times wider at "
      "the tip\n"
      "                         (default 0.5)\n"
      "  --control N            trajectory control points (default 8)\n"
      "  --macro-tol T          macro-cluster shape tolerance, relative "
      "to the\n"
      "                         cluster length (default 0.05; 0 = off)\n"
      "  --database PATH        HRIR database to name in the scene\n"
      "  --mesh PATH            opaque head mesh (OBJ/PLY) for the scene\n"
      "  --frames A-B           INPUT is a per-frame pattern "
      "(frame_%%04d.hair):\n"
      "                         frame A defines the clusters, every frame is\n"
      "                         re-fitted onto them as keyframes\n"
      "  --fps F                frame rate of such an animation (default 24)\n"
      "  --seed N               clustering and placement seed (default "
      "1)\n"
      "  --threads N            threads (0 = all cores)\n"
      "  -q, --quiet            no progress bar or summary\n"
      "  -h, --help             this help\n",
      PROG);
}

typedef struct options {
  const char *inputs[64];
  int n_inputs;
  const char *output, *vdb, *database, *mesh;
  long clusters, follow, control, threads;
  double voxel, follow_radius, tip_separation, macro_tol;
  uint64_t seed;
  int quiet;
  /* a sequence of per-frame strand files: INPUT is a pattern with %d */
  int sequence;
  long first, last;
  double fps;
} options;

static int has_suffix(const char *s, const char *suffix) {
  size_t n = strlen(s), k = strlen(suffix);
  return n >= k && strcmp(s + n - k, suffix) == 0;
}

/* Reads one input by its signature: "HAIR" or a TressFX version float. */
static satf_status read_input(const char *path, const options *o,
                              satf_strand_set **out, satf_error *err) {
  FILE *f = fopen(path, "rb");
  if (!f)
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot open", path);
  char magic[4] = {0};
  size_t got = fread(magic, 1, 4, f);
  fclose(f);
  if ((got == 4 && memcmp(magic, "HAIR", 4) == 0) || has_suffix(path, ".hair"))
    return satf_hair_read(path, out, err);
  satf_tfx_info info;
  satf_strand_set *guides;
  satf_status st = satf_tfx_read(path, &info, &guides, err);
  if (st != SATF_OK)
    return st;
  satf_follow_params fp;
  fp.count = o->follow >= 0 ? (int)o->follow : info.follow_per_guide;
  fp.radius = o->follow_radius >= 0.0 ? (float)o->follow_radius
                                      : satf_strand_set_root_spacing(guides);
  fp.tip_separation = (float)o->tip_separation;
  fp.seed = o->seed;
  if (fp.count == 0) {
    *out = guides;
    return SATF_OK;
  }
  st = satf_strand_set_add_follow(guides, &fp, out, err);
  satf_strand_set_destroy(guides);
  return st;
}

static void progress_cb(void *ctx, size_t done, size_t total) {
  satf_progress_update(ctx, done, total);
}

typedef struct fit_job {
  const satf_strand_set *strands;
  const int *labels;
  satf_import_fit *fits;
  satf_import_fit_params fp;
  satf_error *errs;
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
      satf_import_fit_cluster(j->strands, members, n, &j->fp, &j->fits[c], err);
  satf_cluster *cl = NULL;
  if (st == SATF_OK)
    st = satf_import_fit_cluster_create(&j->fits[c], &cl, err);
  satf_import_projection proj;
  if (st == SATF_OK)
    st = satf_import_project(j->strands, members, n, cl, &proj, err);
  if (st == SATF_OK) {
    satf_import_estimate_density(&proj, &j->fits[c]);
    satf_import_projection_free(&proj);
  }
  satf_cluster_destroy(cl);
  free(members);
  return st != SATF_OK;
}

static int cmp_float(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
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

/* The VDB path as the scene should name it: its file name when it sits in
 * the scene's directory, else its absolute path. */
static void scene_vdb_name(const char *scene, const char *vdb, char *out,
                           size_t size) {
  char sdir[PATH_MAX], vreal[PATH_MAX], tmp[PATH_MAX];
  snprintf(tmp, sizeof tmp, "%s", scene);
  char *slash = strrchr(tmp, '/');
  if (slash)
    *slash = '\0';
  else
    snprintf(tmp, sizeof tmp, ".");
  if (!realpath(tmp, sdir) || !realpath(vdb, vreal)) {
    snprintf(out, size, "%s", vdb);
    return;
  }
  char *vslash = strrchr(vreal, '/');
  size_t dl = (size_t)(vslash - vreal);
  if (strlen(sdir) == dl && strncmp(sdir, vreal, dl) == 0)
    snprintf(out, size, "%s", vslash + 1);
  else
    snprintf(out, size, "%s", vreal);
}

static int parse_args(int argc, char **argv, options *o) {
  memset(o, 0, sizeof *o);
  o->follow = -1;
  o->follow_radius = -1.0;
  o->tip_separation = 0.5;
  o->control = 8;
  o->macro_tol = 0.05;
  o->seed = 1;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
#define NEED_VALUE                                                             \
  if (!val) {                                                                  \
    fprintf(stderr, "%s: %s needs a value (see --help)\n", PROG, a);           \
    return 2;                                                                  \
  }                                                                            \
  i++;
    if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
      usage(stdout);
      return 1;
    } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
      NEED_VALUE o->output = val;
    } else if (!strcmp(a, "--vdb")) {
      NEED_VALUE o->vdb = val;
    } else if (!strcmp(a, "--mesh")) {
      NEED_VALUE o->mesh = val;
    } else if (!strcmp(a, "--database")) {
      NEED_VALUE o->database = val;
    } else if (!strcmp(a, "--clusters")) {
      NEED_VALUE if (satf_cli_int(PROG, a, val, 1, SATF_IMPORT_MAX_CLUSTERS,
                                  &o->clusters)) return 2;
    } else if (!strcmp(a, "--follow")) {
      NEED_VALUE if (satf_cli_int(PROG, a, val, 0, SATF_STRANDS_MAX_FOLLOW,
                                  &o->follow)) return 2;
    } else if (!strcmp(a, "--frames")) {
      char tail = 0;
      NEED_VALUE if (sscanf(val, "%ld-%ld%c", &o->first, &o->last, &tail) !=
                         2 ||
                     o->first < -10000000 || o->last > 10000000 ||
                     o->last <= o->first) {
        fprintf(stderr, "%s: --frames: expected A-B with A < B, got '%s'\n",
                PROG, val);
        return 2;
      }
      o->sequence = 1;
    } else if (!strcmp(a, "--fps")) {
      NEED_VALUE if (satf_cli_double(PROG, a, val, 0.001, 1000.0,
                                     &o->fps)) return 2;
    } else if (!strcmp(a, "--control")) {
      NEED_VALUE if (satf_cli_int(PROG, a, val, 2, 64, &o->control)) return 2;
    } else if (!strcmp(a, "--threads")) {
      NEED_VALUE if (satf_cli_int(PROG, a, val, 0, 256, &o->threads)) return 2;
    } else if (!strcmp(a, "--voxel")) {
      NEED_VALUE if (satf_cli_double(PROG, a, val, 1e-6, 1e6,
                                     &o->voxel)) return 2;
    } else if (!strcmp(a, "--follow-radius")) {
      NEED_VALUE if (satf_cli_double(PROG, a, val, 0.0, 1e6,
                                     &o->follow_radius)) return 2;
    } else if (!strcmp(a, "--tip-separation")) {
      NEED_VALUE if (satf_cli_double(PROG, a, val, 0.0, 100.0,
                                     &o->tip_separation)) return 2;
    } else if (!strcmp(a, "--macro-tol")) {
      NEED_VALUE if (satf_cli_double(PROG, a, val, 0.0, 1.0,
                                     &o->macro_tol)) return 2;
    } else if (!strcmp(a, "--seed")) {
      NEED_VALUE if (satf_cli_u64(PROG, a, val, &o->seed)) return 2;
    } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
      o->quiet = 1;
    } else if (a[0] == '-' && a[1] != '\0') {
      fprintf(stderr, "%s: unknown option %s (see --help)\n", PROG, a);
      return 2;
    } else if (o->n_inputs < 64) {
      o->inputs[o->n_inputs++] = a;
    } else {
      fprintf(stderr, "%s: at most 64 input files\n", PROG);
      return 2;
    }
  }
  if (o->sequence) {
    /* one pattern, one integer conversion, no other % */
    int conv = 0, ok = o->n_inputs == 1;
    for (const char *p = ok ? o->inputs[0] : ""; *p && ok; p++)
      if (*p == '%') {
        const char *q = p + 1;
        while (*q >= '0' && *q <= '9')
          q++;
        ok = *q == 'd' && conv++ == 0;
        p = q;
      }
    if (!ok || conv != 1) {
      fprintf(stderr,
              "%s: --frames needs one INPUT pattern with one integer "
              "conversion, e.g. frame_%%04d.hair\n",
              PROG);
      return 2;
    }
    if (o->vdb) {
      fprintf(stderr,
              "%s: --vdb cannot follow a strand sequence (the grid would be "
              "the first frame's); leave it out\n",
              PROG);
      return 2;
    }
    o->macro_tol = 0.0; /* clusters move independently */
  }
  if (o->n_inputs == 0 || !o->output) {
    fprintf(stderr, "%s: need INPUT files and -o SCENE.json (see --help)\n",
            PROG);
    return 2;
  }
  return 0;
}

static double peak_rss_mb(void) {
  struct rusage ru;
  return getrusage(RUSAGE_SELF, &ru) == 0 ? ru.ru_maxrss / 1024.0 : 0.0;
}

static void frame_path(const char *pattern, long frame, char *out,
                       size_t size) {
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
  snprintf(out, size, pattern, (int)frame); /* checked in parse_args */
#pragma GCC diagnostic pop
}

static cJSON *floats_json(const float *v, int n) {
  cJSON *a = cJSON_CreateArray();
  for (int i = 0; i < n; i++)
    cJSON_AddItemToArray(a, cJSON_CreateNumber((double)v[i]));
  return a;
}

/* Re-fits every frame of a strand sequence onto the clusters of its first
 * frame (same member strands) and writes the fits as keyframes of the
 * scene: each macro-cluster (one cluster each) gets a key per frame on its
 * trajectory, A, B and twist. */
static satf_status add_sequence_keys(const options *o, const fit_job *proto,
                                     int n_clusters, int n_strands,
                                     const satf_import_macro *macro,
                                     satf_error *err) {
  size_t len = 0;
  char *text = NULL;
  FILE *f = fopen(o->output, "rb");
  if (f) {
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    text = n > 0 ? malloc((size_t)n + 1) : NULL;
    if (text)
      len = fread(text, 1, (size_t)n, f);
    fclose(f);
  }
  cJSON *root = text ? cJSON_ParseWithLength(text, len) : NULL;
  free(text);
  if (!root)
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot re-read the scene",
                          o->output);
  cJSON *anim = cJSON_CreateObject(), *range = cJSON_CreateArray();
  cJSON_AddNumberToObject(anim, "fps", o->fps > 0 ? o->fps : 24.0);
  cJSON_AddItemToArray(range, cJSON_CreateNumber((double)o->first));
  cJSON_AddItemToArray(range, cJSON_CreateNumber((double)o->last));
  cJSON_AddItemToObject(anim, "frames", range);
  cJSON_AddItemToObject(root, "animation", anim);
  cJSON *macros = cJSON_GetObjectItemCaseSensitive(root, "macro_clusters");
  satf_status st = SATF_OK;
  satf_progress bar;
  satf_progress_begin(&bar, stderr, "frames", "frames", 1, o->quiet);
  for (long fr = o->first; fr <= o->last && st == SATF_OK; fr++) {
    char path[PATH_MAX];
    frame_path(o->inputs[0], fr, path, sizeof path);
    satf_strand_set *set = NULL;
    st = read_input(path, o, &set, err);
    if (st == SATF_OK && satf_strand_set_count(set) != n_strands)
      st =
          satf_error_set(err, SATF_ERR_FORMAT,
                         "%s: %d strands, but frame %ld had %d: a sequence "
                         "must keep its strands",
                         path, satf_strand_set_count(set), o->first, n_strands);
    satf_import_fit *fits = calloc((size_t)n_clusters, sizeof *fits);
    satf_error *errs = calloc((size_t)n_clusters, sizeof *errs);
    if (st == SATF_OK && (!fits || !errs))
      st = satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
    if (st == SATF_OK) {
      fit_job job = *proto;
      job.strands = set;
      job.fits = fits;
      job.errs = errs;
      if (satf_parallel_for((size_t)n_clusters, (int)o->threads, fit_one, &job,
                            NULL, NULL) != 0) {
        st = satf_error_set(err, SATF_ERR_FORMAT, "%s: fitting failed", path);
        for (int c = 0; c < n_clusters; c++)
          if (errs[c].message[0]) {
            satf_error_set(err, SATF_ERR_FORMAT, "%s: %s", path,
                           errs[c].message);
            break;
          }
      }
    }
    for (int m = 0; st == SATF_OK && m < macro->n_macro; m++) {
      const satf_import_fit *fit = &fits[macro->prototype[m]];
      cJSON *proto_json = cJSON_GetObjectItemCaseSensitive(
          cJSON_GetArrayItem(macros, m), "prototype");
      cJSON *keys = cJSON_GetObjectItemCaseSensitive(proto_json, "keys");
      if (!keys) {
        keys = cJSON_CreateArray();
        cJSON_AddItemToObject(proto_json, "keys", keys);
      }
      cJSON *key = cJSON_CreateObject(), *traj = cJSON_CreateArray();
      cJSON_AddNumberToObject(key, "frame", (double)fr);
      for (int i = 0; i < fit->n_ctrl; i++)
        cJSON_AddItemToArray(traj, floats_json(fit->traj + 3 * i, 3));
      cJSON_AddItemToObject(key, "trajectory", traj);
      cJSON_AddItemToObject(key, "a", floats_json(fit->a, fit->n_radius));
      cJSON_AddItemToObject(key, "b", floats_json(fit->b, fit->n_radius));
      cJSON_AddItemToObject(key, "twist",
                            floats_json(fit->twist, fit->n_radius));
      cJSON_AddItemToArray(keys, key);
    }
    for (int c = 0; fits && c < n_clusters; c++)
      satf_import_fit_free(&fits[c]);
    free(fits);
    free(errs);
    satf_strand_set_destroy(set);
    satf_progress_update(&bar, (size_t)(fr - o->first + 1),
                         (size_t)(o->last - o->first + 1));
  }
  satf_progress_end(&bar);
  char *out = st == SATF_OK ? cJSON_Print(root) : NULL;
  cJSON_Delete(root);
  if (st == SATF_OK && !out)
    st = satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  if (st == SATF_OK)
    st = satf_write_file_atomic(o->output, out, strlen(out), err);
  free(out);
  return st;
}

int main(int argc, char **argv) {
  options o;
  int rc = parse_args(argc, argv, &o);
  if (rc)
    return rc == 1 ? 0 : rc;
  double t0 = satf_now_seconds();
  satf_error err;
  char mesh_path[PATH_MAX];
  if (o.mesh) { /* check it now, and name it absolutely in the scene */
    satf_mesh *probe = NULL;
    if (satf_mesh_read(o.mesh, &probe, &err) != SATF_OK) {
      fprintf(stderr, "%s: --mesh: %s\n", PROG, err.message);
      return 1;
    }
    satf_mesh_destroy(probe);
    if (!realpath(o.mesh, mesh_path))
      snprintf(mesh_path, sizeof mesh_path, "%s", o.mesh);
  }
  satf_strand_set *all = NULL;
  char first_frame[PATH_MAX];
  if (o.sequence) /* the first frame defines the clusters */
    frame_path(o.inputs[0], o.first, first_frame, sizeof first_frame);
  for (int i = 0; i < o.n_inputs; i++) {
    satf_strand_set *s;
    if (read_input(o.sequence ? first_frame : o.inputs[i], &o, &s, &err) !=
        SATF_OK) {
      fprintf(stderr, "%s: %s\n", PROG, err.message);
      satf_strand_set_destroy(all);
      return 1;
    }
    if (!all) {
      all = s;
      continue;
    }
    satf_strand_set *both;
    satf_status st = satf_strand_set_concat(all, s, &both, &err);
    satf_strand_set_destroy(all);
    satf_strand_set_destroy(s);
    if (st != SATF_OK) {
      fprintf(stderr, "%s: %s\n", PROG, err.message);
      return 1;
    }
    all = both;
  }
  int n_strands = satf_strand_set_count(all);
  double t_read = satf_now_seconds();

  /* 1. clusters */
  satf_import_cluster_params cp = satf_import_cluster_params_default();
  cp.clusters = (int)o.clusters;
  cp.seed = o.seed;
  cp.threads = (int)o.threads;
  int *labels = malloc((size_t)n_strands * sizeof(int));
  int n_clusters = 0;
  float rms = 0.0f;
  satf_progress bar;
  satf_progress_begin(&bar, stderr, "clustering", "iterations", 1, o.quiet);
  satf_status st = labels
                       ? satf_import_kmeans(all, &cp, labels, &n_clusters, &rms,
                                            progress_cb, &bar, &err)
                       : satf_error_set(&err, SATF_ERR_NOMEM, "out of memory");
  satf_progress_end(&bar);
  if (st != SATF_OK) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    free(labels);
    satf_strand_set_destroy(all);
    return 1;
  }
  double t_cluster = satf_now_seconds();

  /* 2. fits */
  satf_import_fit *fits = calloc((size_t)n_clusters, sizeof *fits);
  satf_error *errs = calloc((size_t)n_clusters, sizeof *errs);
  fit_job job = {all, labels, fits, satf_import_fit_params_default(), errs};
  job.fp.n_ctrl = (int)o.control;
  job.fp.samples = job.fp.n_ctrl * 4 > 32 ? job.fp.n_ctrl * 4 : 32;
  job.fp.min_radius = 0.5f * satf_strand_set_root_spacing(all);
  satf_progress_begin(&bar, stderr, "fitting", "clusters", 1, o.quiet);
  int bad = !fits || !errs ||
            satf_parallel_for((size_t)n_clusters, (int)o.threads, fit_one, &job,
                              progress_cb, &bar) != 0;
  satf_progress_end(&bar);
  if (bad) {
    const char *why = "out of memory";
    for (int c = 0; errs && c < n_clusters; c++)
      if (errs[c].message[0]) {
        why = errs[c].message;
        break;
      }
    fprintf(stderr, "%s: fitting failed: %s\n", PROG, why);
    rc = 1;
    goto done;
  }
  double t_fit = satf_now_seconds();

  /* 3. macro-clusters */
  satf_import_macro macro;
  if (satf_import_find_macro(fits, n_clusters, (float)o.macro_tol, &macro,
                             &err) != SATF_OK) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    rc = 1;
    goto done;
  }

  /* 4. density grid */
  double t_vdb0 = satf_now_seconds(), vdb_mass = 0.0;
  float voxel = 0.0f;
  char vdb_name[PATH_MAX];
  if (o.vdb) {
    float lo[3], hi[3];
    satf_strand_set_bounds(all, lo, hi);
    float diag = sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                       (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    voxel =
        o.voxel > 0.0 ? (float)o.voxel : default_voxel(fits, n_clusters, diag);
    satf_vdb_builder *b = NULL;
    satf_progress_begin(&bar, stderr, "density", "strands", 1, o.quiet);
    st = satf_import_build_vdb(all, labels, fits, voxel, &b, progress_cb, &bar,
                               &err);
    satf_progress_end(&bar);
    if (st == SATF_OK)
      st = satf_vdb_builder_write(b, o.vdb, "density", &err);
    if (st == SATF_OK) {
      satf_vdb_grid *g = NULL;
      if (satf_vdb_builder_to_grid(b, &g, &err) == SATF_OK)
        vdb_mass = satf_vdb_total_mass(g);
      satf_vdb_grid_destroy(g);
    }
    satf_vdb_builder_destroy(b);
    if (st != SATF_OK) {
      fprintf(stderr, "%s: %s\n", PROG, err.message);
      satf_import_macro_free(&macro);
      rc = 1;
      goto done;
    }
    scene_vdb_name(o.output, o.vdb, vdb_name, sizeof vdb_name);
  }
  double t_vdb = satf_now_seconds();

  /* 5. scene */
  char desc[512];
  snprintf(desc, sizeof desc,
           "imported by satf-import from %s%s: %d strands in %d clusters "
           "(%d macro-clusters)",
           o.inputs[0], o.n_inputs > 1 ? " and more" : "", n_strands,
           n_clusters, macro.n_macro);
  satf_import_scene_options so = {
      o.vdb ? vdb_name : NULL,  "density", o.database, desc, 0, 0, o.seed,
      o.mesh ? mesh_path : NULL};
  st = satf_import_write_scene(o.output, fits, n_clusters, &macro, &so, &err);
  if (st == SATF_OK && o.sequence)
    st = add_sequence_keys(&o, &job, n_clusters, n_strands, &macro, &err);
  if (st != SATF_OK) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    satf_import_macro_free(&macro);
    rc = 1;
    goto done;
  }
  double t_end = satf_now_seconds();
  if (!o.quiet) {
    size_t points = 0, inside = 0;
    double dist = 0.0, width = 0.0;
    int gradient = 0;
    for (int c = 0; c < n_clusters; c++) {
      points += fits[c].points;
      inside += fits[c].inside;
      dist += fits[c].distance_sum;
      width += fits[c].strand_width;
      gradient += fits[c].layout == SATF_SCENE_LAYOUT_GRADIENT;
    }
    char b1[32], b2[32];
    printf("%s: %s\n", PROG, o.output);
    printf("  strands          %d (%zu points, from %d file%s)\n", n_strands,
           satf_strand_set_point_count(all), o.n_inputs,
           o.n_inputs > 1 ? "s" : "");
    printf("  clusters         %d (%s; k-means RMS %.4g)\n", n_clusters,
           o.clusters ? "as asked" : "chosen from the data", rms);
    printf("  macro-clusters   %d (tolerance %g): %s -> %s of cluster "
           "parameters\n",
           macro.n_macro, o.macro_tol,
           satf_format_bytes((double)macro.bytes_separate, b1, sizeof b1),
           satf_format_bytes((double)macro.bytes_shared, b2, sizeof b2));
    printf("  fit quality      %.1f%% of strand points inside their "
           "cluster's envelope;\n"
           "                   mean distance to the trajectory %.4g\n",
           points ? 100.0 * (double)inside / (double)points : 0.0,
           points ? dist / (double)points : 0.0);
    printf("  density          mean strand width %.3g cluster radii; %d of "
           "%d clusters \"gradient\", the rest \"uniform\"\n",
           width / n_clusters, gradient, n_clusters);
    if (o.vdb)
      printf("  vdb              %s (voxel %.4g, mass %.4g)\n", o.vdb,
             (double)voxel, vdb_mass);
    printf("  time             %.2f s (read %.2f, cluster %.2f, fit %.2f, "
           "vdb %.2f, scene %.2f); peak memory %.0f MB\n",
           t_end - t0, t_read - t0, t_cluster - t_read, t_fit - t_cluster,
           t_vdb - t_vdb0, t_end - t_vdb, peak_rss_mb());
  }
  satf_import_macro_free(&macro);
done:
  for (int c = 0; fits && c < n_clusters; c++)
    satf_import_fit_free(&fits[c]);
  free(fits);
  free(errs);
  free(labels);
  satf_strand_set_destroy(all);
  return rc;
}
