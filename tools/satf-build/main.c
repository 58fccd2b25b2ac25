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

int main(int argc, char **argv) {
  satf_build_params p = satf_build_params_default();
  const char *out = NULL;
  long threads = 0, v;
  int quiet = 0;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    const char *val = i + 1 < argc ? argv[i + 1] : NULL;
#define NEED_VALUE                                                             \
  if (!val) {                                                                  \
    fprintf(stderr, "%s: %s needs a value (see --help)\n", PROG, a);           \
    return 2;                                                                  \
  }                                                                            \
  i++;
    if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
      usage(stdout);
      return 0;
    } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
      NEED_VALUE out = val;
    } else if (!strcmp(a, "--samples")) {
      NEED_VALUE if (satf_cli_int(PROG, a, val, 1, 1000000, &v)) return 2;
      p.samples = (int)v;
    } else if (!strcmp(a, "--angles")) {
      NEED_VALUE long nv, nl;
      if (strchr(val, 'x')) {
        if (satf_cli_size(PROG, a, val, 1, 1024, &nv, &nl))
          return 2;
      } else {
        if (satf_cli_int(PROG, a, val, 1, 1024, &nv))
          return 2;
        nl = nv;
      }
      p.n_view = (int)nv;
      p.n_light = (int)nl;
    } else if (!strcmp(a, "--width")) {
      NEED_VALUE if (satf_cli_int(PROG, a, val, 2, 4096, &v)) return 2;
      p.trace.width = (int)v;
    } else if (!strcmp(a, "--grid")) {
      NEED_VALUE if (satf_cli_int(PROG, a, val, 4, 1024, &v)) return 2;
      p.grid = (int)v;
    } else if (!strcmp(a, "--seed")) {
      NEED_VALUE if (satf_cli_u64(PROG, a, val, &p.seed)) return 2;
    } else if (!strcmp(a, "--threads")) {
      NEED_VALUE if (satf_cli_int(PROG, a, val, 0, 1024, &threads)) return 2;
    } else if (!strcmp(a, "--extinction")) {
      double k;
      NEED_VALUE if (satf_cli_double(PROG, a, val, 0.0, 1e6, &k)) return 2;
      p.trace.extinction = (float)k;
    } else if (!strcmp(a, "--no-shadow")) {
      p.trace.self_shadow = 0;
    } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
      quiet = 1;
    } else {
      fprintf(stderr, "%s: unknown option '%s' (see --help)\n", PROG, a);
      return 2;
    }
#undef NEED_VALUE
  }
  if (!out) {
    fprintf(stderr, "%s: no output file: give -o DATABASE.exr (see --help)\n",
            PROG);
    return 2;
  }
  satf_error err;
  satf_error_clear(&err);
  if (satf_build_params_check(&p, &err) != SATF_OK) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    return 2;
  }
  int nthreads = threads > 0 ? (int)threads : satf_cpu_count();
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
  char size[32];
  double records = (double)per * p.samples;
  printf(
      "%s: wrote %s\n"
      "  records   %.0f HRIRs (%d samples x %dx%d azimuths), %d values each\n"
      "  file      %s\n"
      "  time      %.2f s (trace %.2f s, write %.2f s)\n"
      "  speed     %.0f HRIRs/s on %d thread%s\n",
      PROG, out, records, p.samples, p.n_view, p.n_light, p.trace.width,
      satf_format_bytes((double)satf_file_size(out), size, sizeof size),
      t_total, t_build, t_total - t_build, records / t_build, nthreads,
      nthreads == 1 ? "" : "s");
  return 0;
}
