/* satf-db - inspect, verify, export and query HRIR databases. */
#define _POSIX_C_SOURCE 200809L
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "satf/db.h"
#include "satf/math.h"

static const char *PROG = "satf-db";

static void usage(FILE *out) {
  fprintf(
      out,
      "usage: %s COMMAND DATABASE [options]\n"
      "\n"
      "commands:\n"
      "  info FILE             print the build parameters and a summary (of\n"
      "                        a shard: its place in the build)\n"
      "  verify FILE           check the file's integrity; exit 0 if intact,\n"
      "                        1 if damaged or unreadable\n"
      "  atlas FILE -o OUT.exr write an RGBA atlas (R=G=B reflectance, A "
      "alpha)\n"
      "                        for viewers that do not show Y/A images; the\n"
      "                        database itself is already an EXR image\n"
      "  merge SHARD... -o OUT.exr\n"
      "                        join the shard files of satf-build --shard I/N\n"
      "                        (every I of one build once, any order) into\n"
      "                        the database the build writes without --shard\n"
      "  lookup FILE --rho D,S,T --view DEG --light DEG [--k N]\n"
      "                        print one SATF look-up (eq. 4)\n"
      "  -h, --help            this help\n",
      PROG);
}

static int load(const char *path, satf_db **db) {
  satf_error err;
  satf_error_clear(&err);
  if (satf_db_read(path, db, &err) != SATF_OK) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    return 1;
  }
  return 0;
}

/* info and verify of a shard file (satf-build --shard I/N): its place in
 * the build, checked against its own hash. Returns -1 when path is not a
 * shard (the database reader then says what it is). */
static int shard_describe(const char *path) {
  satf_db_part *q = NULL;
  satf_error err;
  satf_error_clear(&err);
  satf_status st = satf_db_part_read(path, &q, &err);
  if (st == SATF_ERR_FORMAT)
    return -1;
  if (st != SATF_OK) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    return 1;
  }
  printf("%s: satf database shard %d/%d: samples %d..%d of a %d-sample "
         "build (seed %" PRIu64 ", %dx%d azimuths, width %d); hash %016" PRIx64
         " ok; join the %d shards with: %s merge SHARD... -o DB.exr\n",
         path, q->index, q->parts, q->first, q->first + q->count - 1,
         q->p.samples, q->p.seed, q->p.n_view, q->p.n_light, q->p.trace.width,
         satf_db_part_hash(q), q->parts, PROG);
  satf_db_part_destroy(q);
  return 0;
}

/* The fibre tracer's parameters (format version 2, satf/db.h). */
static void print_fiber(const satf_build_params *p) {
  const satf_fiber_trace_params *f = &p->fiber;
  printf("  tracing       2-D fibre path tracing: eta %g, radial roughness "
         "%g, %d sub-rays per sample, at most %d bounces\n",
         (double)f->eta, (double)f->beta_n, f->sub_rays, f->max_bounces);
  printf("  channels      %d: Y (R+TT0+TRT0+MS0), A, R_lobe, TT, TRT, MS at "
         "sigma_a",
         satf_build_params_channels(p));
  for (int k = 0; k < f->levels; k++)
    printf("%s%g", k ? ", " : " ", (double)f->sigma_a[k]);
  printf(" per unit fibre radius\n");
}

static int cmd_info(const char *path) {
  int shard = shard_describe(path);
  if (shard >= 0)
    return shard;
  satf_db *db = NULL;
  if (load(path, &db))
    return 1;
  const satf_build_params *p = satf_db_params(db);
  float lo[3], hi[3];
  satf_db_feature_range(db, lo, hi);
  char size[32];
  printf("%s: satf HRIR database, format version %d (%s records)\n", path,
         satf_build_params_version(p), satf_record_kind_name(p->kind));
  printf("  file          %s\n",
         satf_format_bytes((double)satf_file_size(path), size, sizeof size));
  printf("  samples       %d sectors\n", p->samples);
  printf("  azimuths      %d view x %d light\n", p->n_view, p->n_light);
  printf("  records       %lld HRIRs of %d samples (%s)\n",
         (long long)p->samples * p->n_view * p->n_light, p->trace.width,
         p->kind == SATF_RECORD_FIBER ? "fibre lobes" : "reflectance + alpha");
  printf("  seed          %" PRIu64 "\n", p->seed);
  printf("  grid          %d x %d density nodes\n", p->grid, p->grid);
  printf("  sector        r %.3g..%.3g, phase span %.4g rad\n",
         (double)p->shape.r_inner, (double)p->shape.r_outer,
         (double)p->shape.phase_span);
  if (p->kind == SATF_RECORD_FIBER)
    print_fiber(p);
  else
    printf("  tracing       extinction %g, Phong ka %g kd %g ks %g n %g, "
           "epsilon %g, self-shadow %s, smoothing %gx strand width\n",
           (double)p->trace.extinction, (double)p->trace.ambient,
           (double)p->trace.diffuse, (double)p->trace.specular,
           (double)p->trace.shininess, (double)p->trace.epsilon,
           p->trace.self_shadow ? "on" : "off", (double)p->trace.smooth_ratio);
  printf("  rho_st        %.4f .. %.4f (mean density)\n", (double)lo[0],
         (double)hi[0]);
  printf("  rho_s         %.4f .. %.4f (density centroid along s)\n",
         (double)lo[1], (double)hi[1]);
  printf("  rho_t         %.4f .. %.4f (density centroid along t)\n",
         (double)lo[2], (double)hi[2]);
  printf("  integrity     hash %016" PRIx64 " ok\n", satf_db_payload_hash(db));
  satf_db_destroy(db);
  return 0;
}

static int cmd_verify(const char *path) {
  int shard = shard_describe(path);
  if (shard >= 0)
    return shard;
  satf_db *db = NULL;
  if (load(path, &db))
    return 1;
  satf_error err;
  if (satf_exr_check_layout(path, &err) != SATF_OK) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    satf_db_destroy(db);
    return 1;
  }
  printf("%s: ok (hash %016" PRIx64 ")\n", path, satf_db_payload_hash(db));
  satf_db_destroy(db);
  return 0;
}

static int cmd_atlas(const char *path, const char *out) {
  satf_file_role files[] = {{"the database", path, 0}, {"-o", out, 1}};
  satf_error err;
  if (satf_check_distinct_files(files, 2, &err) != SATF_OK ||
      satf_check_output_extension("-o", out, ".exr", "an OpenEXR image",
                                  &err)) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    return 2;
  }
  satf_db *db = NULL;
  if (load(path, &db))
    return 1;
  int w, h;
  satf_db_atlas_size(db, &w, &h);
  satf_error_clear(&err);
  satf_status st = satf_db_write_atlas(db, out, &err);
  satf_db_destroy(db);
  if (st != SATF_OK) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    return 1;
  }
  printf("%s: wrote %dx%d atlas %s\n", PROG, w, h, out);
  return 0;
}

static int parse_rho(const char *text, float rho[3]) {
  char buf[128];
  snprintf(buf, sizeof buf, "%s", text);
  char *save = NULL, *tok = strtok_r(buf, ",", &save);
  for (int i = 0; i < 3; i++) {
    double v;
    if (!tok || satf_cli_double(PROG, "--rho", tok, -1e6, 1e6, &v))
      return -1;
    rho[i] = (float)v;
    tok = strtok_r(NULL, ",", &save);
  }
  return tok ? -1 : 0;
}

typedef struct lookup_opts {
  float rho[3];
  double view, light;
  long k;
} lookup_opts;

/* Parses the options after "lookup FILE"; returns 0 or the exit status 2. */
static int parse_lookup(int argc, char **argv, lookup_opts *o) {
  int have_rho = 0;
  satf_cli_args it;
  satf_cli_begin(&it, PROG, argc, argv);
  it.next = 3;
  it.hint = "";
  while (satf_cli_next(&it)) {
    const char *val; /* every lookup option takes a value */
    if (satf_cli_value(&it, &val))
      return 2;
    if (satf_cli_is(&it, NULL, "--rho")) {
      if (parse_rho(val, o->rho)) {
        fprintf(stderr, "%s: --rho: expected D,S,T\n", PROG);
        return 2;
      }
      have_rho = 1;
    } else if (satf_cli_is(&it, NULL, "--view")) {
      if (satf_cli_double(PROG, "--view", val, -1e4, 1e4, &o->view))
        return 2;
    } else if (satf_cli_is(&it, NULL, "--light")) {
      if (satf_cli_double(PROG, "--light", val, -1e4, 1e4, &o->light))
        return 2;
    } else if (satf_cli_is(&it, NULL, "--k")) {
      if (satf_cli_int(PROG, "--k", val, 1, 16, &o->k))
        return 2;
    } else {
      return satf_cli_unknown(&it);
    }
  }
  if (!have_rho) {
    fprintf(stderr, "%s: lookup needs --rho D,S,T\n", PROG);
    return 2;
  }
  return 0;
}

static int cmd_lookup(const char *path, int argc, char **argv) {
  lookup_opts o = {{0, 0.5f, 0.5f}, 0, 0, 1};
  int rc = parse_lookup(argc, argv, &o);
  if (rc)
    return rc;
  satf_db *db = NULL;
  if (load(path, &db))
    return 1;
  int w = satf_db_width(db);
  float *re = malloc(2 * (size_t)w * sizeof(float)), *al = re + w;
  if (!re) {
    satf_db_destroy(db);
    return 1;
  }
  satf_db_lookup(db, o.rho, (float)(o.view * SATF_PI / 180.0),
                 (float)(o.light * SATF_PI / 180.0), (int)o.k, re, al);
  printf("j\treflectance\talpha\n");
  for (int j = 0; j < w; j++)
    printf("%d\t%.5f\t%.5f\n", j, (double)re[j], (double)al[j]);
  free(re);
  satf_db_destroy(db);
  return 0;
}

/* merge SHARD... -o OUT.exr: argv[2..] */
static int cmd_merge(int argc, char **argv) {
  const char *out = NULL;
  const char **shards = calloc((size_t)argc, sizeof *shards);
  int n = 0;
  if (!shards)
    return 1;
  for (int i = 2; i < argc; i++) {
    if (!strcmp(argv[i], "-o") || !strcmp(argv[i], "--output")) {
      if (i + 1 >= argc || out) {
        fprintf(stderr, "%s: merge: give -o OUT.exr once\n", PROG);
        free(shards);
        return 2;
      }
      out = argv[++i];
    } else {
      shards[n++] = argv[i];
    }
  }
  satf_error err;
  satf_error_clear(&err);
  if (!out || n == 0) {
    fprintf(stderr, "%s: usage: merge SHARD... -o OUT.exr\n", PROG);
    free(shards);
    return 2;
  }
  int rc = 2;
  satf_file_role *files = calloc((size_t)n + 1, sizeof *files);
  if (files) {
    for (int i = 0; i < n; i++)
      files[i] = (satf_file_role){"a shard", shards[i], 0};
    files[n] = (satf_file_role){"-o", out, 1};
    rc = satf_check_distinct_files(files, n + 1, &err) != SATF_OK ||
                 satf_check_output_extension("-o", out, ".exr",
                                             "an OpenEXR database", &err)
             ? 2
             : -1;
    if (rc == 2)
      fprintf(stderr, "%s: %s\n", PROG, err.message);
  }
  free(files);
  satf_db *db = NULL;
  if (rc < 0 && satf_db_merge(shards, n, &db, &err) == SATF_OK &&
      satf_db_write(db, out, &err) == SATF_OK) {
    printf("%s: merged %d shard%s into %s (%d samples, hash %016" PRIx64 ")\n",
           PROG, n, n == 1 ? "" : "s", out, satf_db_samples(db),
           satf_db_payload_hash(db));
    rc = 0;
  } else if (rc < 0) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    rc = 1;
  }
  satf_db_destroy(db);
  free(shards);
  return rc;
}

int main(int argc, char **argv) {
  if (argc < 2 || !strcmp(argv[1], "-h") || !strcmp(argv[1], "--help")) {
    usage(argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  const char *cmd = argv[1];
  if (argc < 3) {
    fprintf(stderr, "%s: %s needs a database file (see --help)\n", PROG, cmd);
    return 2;
  }
  const char *path = argv[2];
  if (!strcmp(cmd, "info"))
    return argc == 3 ? cmd_info(path)
                     : (fprintf(stderr, "%s: info takes one file\n", PROG), 2);
  if (!strcmp(cmd, "verify"))
    return argc == 3
               ? cmd_verify(path)
               : (fprintf(stderr, "%s: verify takes one file\n", PROG), 2);
  if (!strcmp(cmd, "atlas")) {
    if (argc != 5 || (strcmp(argv[3], "-o") && strcmp(argv[3], "--output"))) {
      fprintf(stderr, "%s: usage: atlas FILE -o OUT.exr\n", PROG);
      return 2;
    }
    return cmd_atlas(path, argv[4]);
  }
  if (!strcmp(cmd, "lookup"))
    return cmd_lookup(path, argc, argv);
  if (!strcmp(cmd, "merge"))
    return cmd_merge(argc, argv);
  fprintf(stderr, "%s: unknown command '%s' (see --help)\n", PROG, cmd);
  return 2;
}
