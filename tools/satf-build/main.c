/* satf-build - builds an HRIR database (SATF sec. 5). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "satf/common.h"
#include "satf/offline.h"
#ifdef SATF_MPI
#include "mpi_build.h"
#endif

static const char *PROG = "satf-build";

static void usage(FILE *out) {
  satf_build_params d = satf_build_params_default();
  fprintf(
      out,
      "usage: %s [options] -o DATABASE.exr\n"
      "\n"
      "Builds an HRIR database: random generalized sectors are ray traced in\n"
      "their own plane under every view x light azimuth pair (SATF paper\n"
      "sec. 5). The output is an OpenEXR image whose pixels are the records.\n"
      "\n"
      "options:\n"
      "  -o, --output PATH   database file to write (required)\n"
      "  --samples N         random sectors (default %d)\n"
      "  --angles N|VxL      view x light azimuths over the circle (default "
      "%dx%d)\n"
      "  --width N           samples per HRIR record (default %d)\n"
      "  --grid N            density grid nodes per side (default %d)\n"
      "  --seed S            random seed (default %" PRIu64 ")\n"
      "  --threads N         worker threads, 0 = all cores (default 0)\n"
      "  --extinction K      opacity per unit density and length (default %g)\n"
      "  --no-shadow         no in-sector self-shadowing (the paper's plain\n"
      "                      version)\n"
      "  --kind phong|fiber  record kind (default phong, format version 1);\n"
      "                      fiber: physically based records, format version\n"
      "                      2 (2-D path tracing of the strands as d'Eon/\n"
      "                      Chiang fibres; default 128 samples, width 16)\n"
      "  --levels A,B,..     fiber: absorption levels, sigma_a per unit fibre\n"
      "                      radius, ascending (default 0,0.2,1,4,16)\n"
      "  --sub-rays N        fiber: eye rays per record sample (default 24)\n"
      "  --radial-roughness B  fiber: beta_n, baked into the records (0.3)\n"
      "  --ior ETA           fiber: index of refraction (default 1.55)\n"
      "  --max-bounces N     fiber: fibre interactions per path (default 64)\n"
      "  --shard I/N         build only part I of N (0 <= I < N) into a\n"
      "                      shard file: independent tasks of a farm queue;\n"
      "                      satf-db merge joins the N shards into the\n"
      "                      database this command writes without --shard\n"
      "  --install-default   write the tools' default database where they\n"
      "                      look when nothing names one: PREFIX/share/satf\n"
      "                      beside this program's bin/ ($SATF_DATA_DIR when\n"
      "                      set); without --kind both the Phong\n"
      "                      (satf-default) and fibre (satf-fiber) ones\n"
      "  -q, --quiet         no progress output\n"
      "  -h, --help          this help\n"
      "\n"
      "Under MPI (mpirun -np N %s ... -o DB.exr) the samples are split\n"
      "across the ranks, each on its --threads, and rank 0 writes the\n"
      "database: the same bytes as one process with the same parameters.\n",
      PROG, d.samples, d.n_view, d.n_light, d.trace.width, d.grid, d.seed,
      (double)d.trace.extinction, PROG);
}

static void on_progress(void *ctx, size_t done, size_t total) {
  satf_progress_update(ctx, done, total);
}

typedef struct options {
  satf_build_params p;
  const char *out;
  long threads;
  int quiet;
  long shard, shards; /* --shard I/N; shards 0: the whole build */
  int width_set;      /* --width given: --kind fiber keeps it */
  int samples_set;    /* --samples given: --kind fiber keeps it */
  int kind_set;       /* --kind given */
  int install;        /* --install-default: -o is the installed default */
  char install_path[4096];
} options;

/* --levels A,B,...: ascending absorption levels. */
static int parse_levels(satf_cli_args *it, satf_fiber_trace_params *f) {
  const char *val;
  if (satf_cli_value(it, &val))
    return -1;
  int n = 0;
  const char *c = val;
  while (*c) {
    char *end = NULL;
    double v = strtod(c, &end);
    if (end == c || n == SATF_DB_LEVELS_MAX || !(v >= 0.0 && v <= 1000.0) ||
        (n > 0 && !(v > f->sigma_a[n - 1])) || (*end && *end != ',')) {
      fprintf(stderr,
              "%s: --levels: expected 1 to %d ascending values in [0, 1000] "
              "separated by commas, got '%s'\n",
              PROG, SATF_DB_LEVELS_MAX, val);
      return -1;
    }
    f->sigma_a[n++] = (float)v;
    c = *end ? end + 1 : end;
  }
  if (n == 0) {
    fprintf(stderr, "%s: --levels: no values\n", PROG);
    return -1;
  }
  f->levels = n;
  return 0;
}

/* The fibre record options; returns 1 when `it` is none of them. */
static int parse_fiber_option(satf_cli_args *it, options *o) {
  satf_fiber_trace_params *f = &o->p.fiber;
  long v;
  double k;
  if (satf_cli_is(it, NULL, "--kind")) {
    const char *val;
    if (satf_cli_value(it, &val))
      return -1;
    if (satf_record_kind_parse(val, &o->p.kind) != 0) {
      fprintf(stderr, "%s: --kind: expected phong or fiber, got '%s'\n", PROG,
              val);
      return -1;
    }
    o->kind_set = 1;
    return 0;
  }
  if (satf_cli_is(it, NULL, "--levels"))
    return parse_levels(it, f);
  if (satf_cli_is(it, NULL, "--sub-rays")) {
    if (satf_cli_value_int(it, 1, 65536, &v))
      return -1;
    f->sub_rays = (int)v;
  } else if (satf_cli_is(it, NULL, "--max-bounces")) {
    if (satf_cli_value_int(it, 1, 10000, &v))
      return -1;
    f->max_bounces = (int)v;
  } else if (satf_cli_is(it, NULL, "--radial-roughness")) {
    if (satf_cli_value_double(it, 1e-3, 1.0, &k))
      return -1;
    f->beta_n = (float)k;
  } else if (satf_cli_is(it, NULL, "--ior")) {
    if (satf_cli_value_double(it, 1.01, 3.99, &k))
      return -1;
    f->eta = (float)k;
  } else {
    return 1;
  }
  return 0;
}

/* --shard I/N */
static int parse_shard(satf_cli_args *it, options *o) {
  const char *val;
  char *end = NULL;
  if (satf_cli_value(it, &val))
    return -1;
  const char *slash = strchr(val, '/');
  long i = -1, n = 0;
  if (slash) {
    i = strtol(val, &end, 10);
    if (end != slash || slash == val)
      i = -1;
    n = strtol(slash + 1, &end, 10);
    if (*end || !slash[1])
      n = 0;
  }
  if (i < 0 || n < 1 || n > 1000000 || i >= n) {
    fprintf(stderr,
            "%s: --shard: expected I/N with 0 <= I < N (e.g. 3/16), got "
            "'%s'\n",
            PROG, val);
    return -1;
  }
  o->shard = i;
  o->shards = n;
  return 0;
}

static int parse_angles(satf_cli_args *it, satf_build_params *p) {
  const char *val;
  long nv, nl;
  if (satf_cli_value(it, &val))
    return -1;
  if (strchr(val, 'x')) {
    if (satf_cli_size(PROG, it->arg, val, 1, 1024, &nv, &nl))
      return -1;
  } else {
    if (satf_cli_int(PROG, it->arg, val, 1, 1024, &nv))
      return -1;
    nl = nv;
  }
  p->n_view = (int)nv;
  p->n_light = (int)nl;
  return 0;
}

/* Parses one option into o; returns -1 on a bad value or unknown option. */
static int parse_option(satf_cli_args *it, options *o) {
  satf_build_params *p = &o->p;
  long v;
  double k;
  if (satf_cli_is(it, "-o", "--output"))
    return satf_cli_value(it, &o->out);
  if (satf_cli_is(it, NULL, "--angles"))
    return parse_angles(it, p);
  if (satf_cli_is(it, NULL, "--seed"))
    return satf_cli_value_u64(it, &p->seed);
  if (satf_cli_is(it, NULL, "--threads"))
    return satf_cli_value_int(it, 0, 1024, &o->threads);
  if (satf_cli_is(it, NULL, "--shard"))
    return parse_shard(it, o);
  int fo = parse_fiber_option(it, o);
  if (fo != 1)
    return fo;
  if (satf_cli_is(it, NULL, "--install-default")) {
    o->install = 1;
  } else if (satf_cli_is(it, NULL, "--no-shadow")) {
    p->trace.self_shadow = 0;
  } else if (satf_cli_is(it, "-q", "--quiet")) {
    o->quiet = 1;
  } else if (satf_cli_is(it, NULL, "--samples")) {
    if (satf_cli_value_int(it, 1, 1000000, &v))
      return -1;
    p->samples = (int)v;
    o->samples_set = 1;
  } else if (satf_cli_is(it, NULL, "--width")) {
    if (satf_cli_value_int(it, 2, 4096, &v))
      return -1;
    p->trace.width = (int)v;
    o->width_set = 1;
  } else if (satf_cli_is(it, NULL, "--grid")) {
    if (satf_cli_value_int(it, 4, 1024, &v))
      return -1;
    p->grid = (int)v;
  } else if (satf_cli_is(it, NULL, "--extinction")) {
    if (satf_cli_value_double(it, 0.0, 1e6, &k))
      return -1;
    p->trace.extinction = (float)k;
  } else {
    satf_cli_unknown(it);
    return -1;
  }
  return 0;
}

/* mkdir -p path; 0 when it is a folder at the end. */
static int make_dirs(const char *path) {
  char buf[4096];
  int len = snprintf(buf, sizeof buf, "%s", path);
  if (len <= 0 || (size_t)len >= sizeof buf)
    return -1;
  for (char *c = buf + 1; *c; c++)
    if (*c == '/') {
      *c = '\0';
      (void)mkdir(buf, 0755); /* an existing one is checked below */
      *c = '/';
    }
  struct stat sb;
  return mkdir(buf, 0755) == 0 || (stat(buf, &sb) == 0 && S_ISDIR(sb.st_mode))
             ? 0
             : -1;
}

/* --install-default: the output is the installed default of the kind, in
 * the folder every tool looks in when nothing names a database. */
static int install_output(options *o) {
  char dir[4096];
  if (o->out) {
    fprintf(stderr, "%s: give -o or --install-default, not both\n", PROG);
    return -1;
  }
  if (o->shards > 0) {
    fprintf(stderr,
            "%s: --install-default builds whole databases, not a "
            "--shard\n",
            PROG);
    return -1;
  }
  if (satf_data_dir(dir, sizeof dir) != 0 || make_dirs(dir) != 0) {
    fprintf(stderr,
            "%s: --install-default: cannot make the data folder %s: "
            "%s\n",
            PROG, dir, strerror(errno));
    return -1;
  }
  int len =
      snprintf(o->install_path, sizeof o->install_path, "%s/%s", dir,
               o->p.kind == SATF_RECORD_FIBER ? "satf-fiber.hrirdb.exr"
                                              : "satf-default.hrirdb.exr");
  if (len <= 0 || (size_t)len >= sizeof o->install_path) {
    fprintf(stderr, "%s: --install-default: %s: path too long\n", PROG, dir);
    return -1;
  }
  o->out = o->install_path;
  return 0;
}

/* Returns -1 to go on, else the exit status. */
static int parse_args(int argc, char **argv, options *o) {
  memset(o, 0, sizeof *o);
  o->p = satf_build_params_default();
  satf_cli_args it;
  satf_cli_begin(&it, PROG, argc, argv);
  while (satf_cli_next(&it)) {
    if (satf_cli_is(&it, "-h", "--help")) {
      usage(stdout);
      return 0;
    }
    if (parse_option(&it, o))
      return 2;
  }
  if (o->p.kind == SATF_RECORD_FIBER && !o->width_set)
    o->p.trace.width = satf_build_params_default_fiber().trace.width;
  if (o->p.kind == SATF_RECORD_FIBER && !o->samples_set)
    o->p.samples = satf_build_params_default_fiber().samples;
  if (o->p.kind == SATF_RECORD_FIBER &&
      o->p.n_light < satf_fiber_trace_min_lights(o->p.fiber.beta_n))
    fprintf(stderr,
            "%s: warning: %d light azimuths are too few for radial roughness "
            "%g (its lobes fall between them: energy is not conserved); use "
            "--angles with at least %d lights\n",
            PROG, o->p.n_light, (double)o->p.fiber.beta_n,
            satf_fiber_trace_min_lights(o->p.fiber.beta_n));
  if (o->install && install_output(o) != 0)
    return 2;
  if (!o->out) {
    fprintf(stderr,
            "%s: no output file: give -o DATABASE.exr or --install-default "
            "(see --help)\n",
            PROG);
    return 2;
  }
  satf_error err;
  if (satf_check_output_extension("-o", o->out, ".exr", "an OpenEXR database",
                                  &err)) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    return 2;
  }
  return -1;
}

/* What the summary reports of a run. */
typedef struct run_times {
  double total, trace, gather; /* gather: MPI ranks to rank 0 */
  int ranks, threads;          /* threads per rank */
} run_times;

static void print_summary(const options *o, const run_times *t) {
  const satf_build_params *p = &o->p;
  char size[32], where[64];
  double samples = p->samples;
  const char *what = "";
  if (o->shards > 0) {
    int first, count;
    satf_db_part_range(p->samples, (int)o->shard, (int)o->shards, &first,
                       &count);
    samples = count;
    what = " (shard)";
  }
  double records = (double)p->n_view * (double)p->n_light * samples;
  if (t->ranks > 1)
    snprintf(where, sizeof where, "%d ranks x %d thread%s", t->ranks,
             t->threads, t->threads == 1 ? "" : "s");
  else
    snprintf(where, sizeof where, "%d thread%s", t->threads,
             t->threads == 1 ? "" : "s");
  printf("%s: wrote %s%s\n"
         "  records   %.0f HRIRs (%.0f samples x %dx%d azimuths), %d values "
         "each\n"
         "  file      %s\n",
         PROG, o->out, what, records, samples, p->n_view, p->n_light,
         p->trace.width,
         satf_format_bytes((double)satf_file_size(o->out), size, sizeof size));
  if (t->ranks > 1)
    printf("  time      %.2f s (trace %.2f s, gather %.2f s, write %.2f s)\n",
           t->total, t->trace, t->gather, t->total - t->trace - t->gather);
  else
    printf("  time      %.2f s (trace %.2f s, write %.2f s)\n", t->total,
           t->trace, t->total - t->trace);
  printf("  speed     %.0f HRIRs/s on %s\n", records / t->trace, where);
}

static void print_start(const options *o, int ranks, int nthreads) {
  const satf_build_params *p = &o->p;
  size_t per = (size_t)p->n_view * (size_t)p->n_light;
  char shard[64] = "", where[64] = "";
  if (o->shards > 0)
    snprintf(shard, sizeof shard, ", shard %ld/%ld", o->shard, o->shards);
  if (ranks > 1)
    snprintf(where, sizeof where, "%d ranks x ", ranks);
  fprintf(stderr,
          "%s: %d sectors x %dx%d azimuths = %zu HRIRs of %d samples, "
          "grid %d, seed %" PRIu64 "%s, %s%d thread%s\n",
          PROG, p->samples, p->n_view, p->n_light, per * (size_t)p->samples,
          p->trace.width, p->grid, p->seed, shard, where, nthreads,
          nthreads == 1 ? "" : "s");
}

/* --shard I/N: one part into a shard file. */
static satf_status build_shard(const options *o, int nthreads,
                               satf_progress *prog, run_times *t,
                               satf_error *err) {
  double t0 = satf_now_seconds();
  satf_db_part *part = NULL;
  satf_status st = satf_build_part(&o->p, (int)o->shard, (int)o->shards,
                                   nthreads, on_progress, prog, &part, err);
  satf_progress_end(prog);
  t->trace = satf_now_seconds() - t0;
  if (st == SATF_OK)
    st = satf_db_part_write(part, o->out, err);
  satf_db_part_destroy(part);
  t->total = satf_now_seconds() - t0;
  return st;
}

/* The whole build in this process. */
static satf_status build_whole(const options *o, int nthreads,
                               satf_progress *prog, run_times *t,
                               satf_error *err) {
  double t0 = satf_now_seconds();
  satf_db *db = NULL;
  satf_status st = satf_build(&o->p, nthreads, on_progress, prog, &db, err);
  satf_progress_end(prog);
  t->trace = satf_now_seconds() - t0;
  if (st == SATF_OK)
    st = satf_db_write_threads(db, o->out, nthreads, err);
  t->total = satf_now_seconds() - t0;
  satf_db_destroy(db);
  return st;
}

/* A long build (hours on a cluster) learns before it starts, not when it
 * writes, that its output cannot be written: the temporary file it will
 * write through is created and removed. Returns -1, or the exit status. */
static int output_writable(const char *path) {
  char tmp[4096];
  satf_error err;
  satf_error_clear(&err);
  struct stat sb;
  if (stat(path, &sb) == 0 && S_ISDIR(sb.st_mode)) {
    fprintf(stderr, "%s: -o %s: is a directory\n", PROG, path);
    return 2;
  }
  FILE *f = NULL;
  if (satf_temp_path(path, tmp, sizeof tmp, &err) == SATF_OK &&
      (f = fopen(tmp, "wb")) != NULL) {
    fclose(f);
    remove(tmp);
    return -1;
  }
  if (err.status == SATF_OK)
    fprintf(stderr, "%s: -o %s: cannot write there: %s\n", PROG, path,
            strerror(errno));
  else
    fprintf(stderr, "%s: %s\n", PROG, err.message);
  return 1;
}

/* Checks the options; returns -1 to go on, else the exit status. */
static int check_options(options *o) {
  satf_error err;
  satf_error_clear(&err);
  if (satf_build_params_check(&o->p, &err) != SATF_OK) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    return 2;
  }
  if (o->shards > o->p.samples) {
    fprintf(stderr, "%s: --shard %ld/%ld: more shards than the %d samples\n",
            PROG, o->shard, o->shards, o->p.samples);
    return 2;
  }
  return output_writable(o->out);
}

#ifdef SATF_MPI
/* Under mpirun: the samples split across the ranks, rank 0 writes. */
static int build_mpi(const satf_mpi *m, const options *o, int nthreads) {
  satf_error err;
  satf_error_clear(&err);
  if (o->shards > 0) {
    if (m->rank == 0)
      fprintf(stderr,
              "%s: --shard is for independent farm-queue tasks; under "
              "mpirun leave it out (the ranks share the build)\n",
              PROG);
    return 2;
  }
  if (!o->quiet && m->rank == 0)
    print_start(o, m->size, nthreads);
  size_t per = (size_t)o->p.n_view * (size_t)o->p.n_light;
  satf_progress prog;
  satf_progress_begin(&prog, stderr, "building", "HRIRs", per,
                      o->quiet || m->rank != 0);
  run_times t = {0, 0, 0, m->size, nthreads};
  satf_mpi_build_times bt = {0, 0};
  double t0 = satf_now_seconds();
  satf_db *db = NULL;
  satf_status st = satf_mpi_build(m, &o->p, nthreads, &prog, &db, &bt, &err);
  satf_progress_end(&prog);
  if (st != SATF_OK)
    satf_mpi_fail(m, PROG, err.message);
  int rc = 0;
  if (m->rank == 0) {
    st = satf_db_write_threads(db, o->out, nthreads, &err);
    satf_db_destroy(db);
    if (st != SATF_OK) {
      fprintf(stderr, "%s: %s\n", PROG, err.message);
      rc = 1;
    }
  }
  t.total = satf_now_seconds() - t0;
  t.trace = bt.trace;
  t.gather = bt.gather;
  rc = satf_mpi_share_status(m, rc);
  if (rc == 0 && m->rank == 0 && !o->quiet)
    print_summary(o, &t);
  return rc;
}
#endif

/* One process: the whole build or one shard. */
static int build_here(const options *o, int nthreads) {
  if (!o->quiet)
    print_start(o, 1, nthreads);
  size_t per = (size_t)o->p.n_view * (size_t)o->p.n_light;
  satf_progress prog;
  satf_progress_begin(&prog, stderr, "building", "HRIRs", per, o->quiet);
  run_times t = {0, 0, 0, 1, nthreads};
  satf_error err;
  satf_error_clear(&err);
  satf_status st = o->shards > 0 ? build_shard(o, nthreads, &prog, &t, &err)
                                 : build_whole(o, nthreads, &prog, &t, &err);
  if (st != SATF_OK) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    return 1;
  }
  if (!o->quiet)
    print_summary(o, &t);
  return 0;
}

/* --install-default without --kind: the fibre database after the Phong
 * one, with the same options. */
static int install_fiber_too(int argc, char **argv) {
  char **args = malloc(((size_t)argc + 3) * sizeof *args);
  if (!args) {
    fprintf(stderr, "%s: out of memory\n", PROG);
    return 1;
  }
  memcpy(args, argv, (size_t)argc * sizeof *args);
  static char kind[] = "--kind", fiber[] = "fiber";
  args[argc] = kind;
  args[argc + 1] = fiber;
  args[argc + 2] = NULL;
  options o;
  int rc = parse_args(argc + 2, args, &o);
  if (rc < 0)
    rc = check_options(&o);
  if (rc < 0)
    rc = build_here(&o, o.threads > 0 ? (int)o.threads : satf_cpu_count());
  free(args);
  return rc;
}

int main(int argc, char **argv) {
#ifdef SATF_MPI
  satf_mpi m;
  if (satf_mpi_start(PROG, &argc, &argv, &m) != 0)
    return 1;
  int muted[2];
  satf_mpi_mute(&m, muted); /* --help and argument errors print once */
#endif
  options o;
  int rc = parse_args(argc, argv, &o);
  if (rc < 0)
    rc = check_options(&o);
  int nthreads = o.threads > 0 ? (int)o.threads : satf_cpu_count();
  int ranks = 1;
#ifdef SATF_MPI
  satf_mpi_unmute(muted);
  rc = satf_mpi_share_status(&m, rc); /* rank 0's output check decides */
  ranks = m.size;
  if (rc < 0 && m.size > 1)
    rc = build_mpi(&m, &o, nthreads);
  satf_mpi_stop(&m);
#endif
  if (rc < 0)
    rc = build_here(&o, nthreads);
  if (rc == 0 && o.install && !o.kind_set && ranks > 1) {
    fprintf(stderr,
            "%s: under mpirun --install-default builds one kind: "
            "run it again with --kind fiber\n",
            PROG);
    return rc;
  }
  if (rc == 0 && o.install && !o.kind_set)
    rc = install_fiber_too(argc, argv);
  return rc;
}
