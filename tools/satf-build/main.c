/* satf-build - builds an HRIR database (SATF sec. 5). */
#include <inttypes.h>
#include <stdio.h>
#include <string.h>

#include "satf/common.h"
#include "satf/offline.h"

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
      "  -q, --quiet         no progress output\n"
      "  -h, --help          this help\n",
      PROG, d.samples, d.n_view, d.n_light, d.trace.width, d.grid, d.seed,
      (double)d.trace.extinction);
}

static void on_progress(void *ctx, size_t done, size_t total) {
  satf_progress_update(ctx, done, total);
}

typedef struct options {
  satf_build_params p;
  const char *out;
  long threads;
  int quiet;
} options;

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
  if (satf_cli_is(it, NULL, "--no-shadow")) {
    p->trace.self_shadow = 0;
  } else if (satf_cli_is(it, "-q", "--quiet")) {
    o->quiet = 1;
  } else if (satf_cli_is(it, NULL, "--samples")) {
    if (satf_cli_value_int(it, 1, 1000000, &v))
      return -1;
    p->samples = (int)v;
  } else if (satf_cli_is(it, NULL, "--width")) {
    if (satf_cli_value_int(it, 2, 4096, &v))
      return -1;
    p->trace.width = (int)v;
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
  if (!o->out) {
    fprintf(stderr, "%s: no output file: give -o DATABASE.exr (see --help)\n",
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

static void print_summary(const options *o, int nthreads, double t_total,
                          double t_build) {
  const satf_build_params *p = &o->p;
  char size[32];
  double records = (double)p->n_view * (double)p->n_light * p->samples;
  printf(
      "%s: wrote %s\n"
      "  records   %.0f HRIRs (%d samples x %dx%d azimuths), %d values each\n"
      "  file      %s\n"
      "  time      %.2f s (trace %.2f s, write %.2f s)\n"
      "  speed     %.0f HRIRs/s on %d thread%s\n",
      PROG, o->out, records, p->samples, p->n_view, p->n_light, p->trace.width,
      satf_format_bytes((double)satf_file_size(o->out), size, sizeof size),
      t_total, t_build, t_total - t_build, records / t_build, nthreads,
      nthreads == 1 ? "" : "s");
}

int main(int argc, char **argv) {
  options o;
  int rc = parse_args(argc, argv, &o);
  if (rc >= 0)
    return rc;
  satf_build_params p = o.p;
  const char *out = o.out;
  int quiet = o.quiet;
  satf_error err;
  satf_error_clear(&err);
  if (satf_build_params_check(&p, &err) != SATF_OK) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    return 2;
  }
  int nthreads = o.threads > 0 ? (int)o.threads : satf_cpu_count();
  size_t per = (size_t)p.n_view * (size_t)p.n_light;
  if (!quiet)
    fprintf(stderr,
            "%s: %d sectors x %dx%d azimuths = %zu HRIRs of %d samples, "
            "grid %d, seed %" PRIu64 ", %d thread%s\n",
            PROG, p.samples, p.n_view, p.n_light, per * (size_t)p.samples,
            p.trace.width, p.grid, p.seed, nthreads, nthreads == 1 ? "" : "s");
  satf_progress prog;
  satf_progress_begin(&prog, stderr, "building", "HRIRs", per, quiet);
  double t0 = satf_now_seconds();
  satf_db *db = NULL;
  satf_status st = satf_build(&p, nthreads, on_progress, &prog, &db, &err);
  satf_progress_end(&prog);
  double t_build = satf_now_seconds() - t0;
  if (st == SATF_OK)
    st = satf_db_write(db, out, &err);
  double t_total = satf_now_seconds() - t0;
  satf_db_destroy(db);
  if (st != SATF_OK) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    return 1;
  }
  print_summary(&o, nthreads, t_total, t_build);
  return 0;
}
