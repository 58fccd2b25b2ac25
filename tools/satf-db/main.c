/* satf-db - inspect, verify, export and query HRIR databases. */
#define _POSIX_C_SOURCE 200809L
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "satf/db.h"

static const char *PROG = "satf-db";

static void usage(FILE *out) {
  fprintf(
      out,
      "usage: %s COMMAND DATABASE [options]\n"
      "\n"
      "commands:\n"
      "  info FILE             print the build parameters and a summary\n"
      "  verify FILE           check the file's integrity; exit 0 if intact,\n"
      "                        1 if damaged or unreadable\n"
      "  atlas FILE -o OUT.exr write an RGBA atlas (R=G=B reflectance, A "
      "alpha)\n"
      "                        for viewers that do not show Y/A images; the\n"
      "                        database itself is already an EXR image\n"
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

static int cmd_info(const char *path) {
  satf_db *db = NULL;
  if (load(path, &db))
    return 1;
  const satf_build_params *p = satf_db_params(db);
  float lo[3], hi[3];
  satf_db_feature_range(db, lo, hi);
  char size[32];
  printf("%s: satf HRIR database, format version %d\n", path,
         SATF_DB_FORMAT_VERSION);
  printf("  file          %s\n",
         satf_format_bytes((double)satf_file_size(path), size, sizeof size));
  printf("  samples       %d sectors\n", p->samples);
  printf("  azimuths      %d view x %d light\n", p->n_view, p->n_light);
  printf("  records       %lld HRIRs of %d samples (reflectance + alpha)\n",
         (long long)p->samples * p->n_view * p->n_light, p->trace.width);
  printf("  seed          %" PRIu64 "\n", p->seed);
  printf("  grid          %d x %d density nodes\n", p->grid, p->grid);
  printf("  sector        r %.3g..%.3g, phase span %.4g rad\n",
         (double)p->shape.r_inner, (double)p->shape.r_outer,
         (double)p->shape.phase_span);
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
  satf_db *db = NULL;
  if (load(path, &db))
    return 1;
  printf("%s: ok (hash %016" PRIx64 ")\n", path, satf_db_payload_hash(db));
  satf_db_destroy(db);
  return 0;
}

static int cmd_atlas(const char *path, const char *out) {
  satf_db *db = NULL;
  if (load(path, &db))
    return 1;
  const satf_build_params *p = satf_db_params(db);
  int w = p->n_view * p->trace.width, h = p->samples * p->n_light;
  satf_error err;
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

static int cmd_lookup(const char *path, int argc, char **argv) {
  float rho[3] = {0, 0.5f, 0.5f};
  double view = 0, light = 0;
  long k = 1;
  int have_rho = 0;
  for (int i = 0; i < argc; i++) {
    const char *val = i + 1 < argc ? argv[i + 1] : NULL;
    if (!val) {
      fprintf(stderr, "%s: %s needs a value\n", PROG, argv[i]);
      return 2;
    }
    if (!strcmp(argv[i], "--rho")) {
      if (parse_rho(val, rho)) {
        fprintf(stderr, "%s: --rho: expected D,S,T\n", PROG);
        return 2;
      }
      have_rho = 1;
    } else if (!strcmp(argv[i], "--view")) {
      if (satf_cli_double(PROG, "--view", val, -1e4, 1e4, &view))
        return 2;
    } else if (!strcmp(argv[i], "--light")) {
      if (satf_cli_double(PROG, "--light", val, -1e4, 1e4, &light))
        return 2;
    } else if (!strcmp(argv[i], "--k")) {
      if (satf_cli_int(PROG, "--k", val, 1, 16, &k))
        return 2;
    } else {
      fprintf(stderr, "%s: unknown option '%s'\n", PROG, argv[i]);
      return 2;
    }
    i++;
  }
  if (!have_rho) {
    fprintf(stderr, "%s: lookup needs --rho D,S,T\n", PROG);
    return 2;
  }
  satf_db *db = NULL;
  if (load(path, &db))
    return 1;
  int w = satf_db_width(db);
  float *re = malloc(2 * (size_t)w * sizeof(float)), *al = re + w;
  if (!re) {
    satf_db_destroy(db);
    return 1;
  }
  satf_db_lookup(db, rho, (float)(view * 3.14159265358979 / 180.0),
                 (float)(light * 3.14159265358979 / 180.0), (int)k, re, al);
  printf("j\treflectance\talpha\n");
  for (int j = 0; j < w; j++)
    printf("%d\t%.5f\t%.5f\n", j, (double)re[j], (double)al[j]);
  free(re);
  satf_db_destroy(db);
  return 0;
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
    return cmd_lookup(path, argc - 3, argv + 3);
  fprintf(stderr, "%s: unknown command '%s' (see --help)\n", PROG, cmd);
  return 2;
}
