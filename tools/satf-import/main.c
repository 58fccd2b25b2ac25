/* satf-import - turns strand hair files (cyHair .hair, TressFX .tfx) into a
 * satf scene: clusters, fitted generalized cylinders, macro-clusters and
 * density (SATF sec. 3.1-3.3), optionally with a world-space OpenVDB
 * density grid. The import itself is satf_import_run (satf/import.h); this
 * reads the command line. */
#define _XOPEN_SOURCE 700
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "satf/common.h"
#include "satf/import.h"

static const char *PROG = "satf-import";

static void usage(FILE *out) {
  fprintf(
      out,
      "usage: %s INPUT... -o SCENE.json [options]\n"
      "\n"
      "Imports strand hair (cyHair .hair, TressFX 3.x/4.x .tfx, strand "
      ".ply with\n"
      "a strand element of point counts or edges, OBJ `l` polylines,\n"
      "USC-HairSalon .data; the format is read from the bytes; several "
      "files go\n"
      "into one scene) as SATF\n"
      "clusters: k-means on the strands, a\n"
      "generalized cylinder fitted to each cluster, macro-clusters for\n"
      "clusters that match after a similarity transform, and density.\n"
      "\n"
      "options:\n"
      "  -o, --output PATH      scene file to write (required)\n"
      "  --clusters N           cluster count (default: chosen from the "
      "data)\n"
      "  --quality Q            draft, default or high: how closely the\n"
      "                         adaptive clusters follow their strands (the\n"
      "                         tolerance is 4%%, 2%% or 1%% of the hair's\n"
      "                         diagonal; tens to thousands of clusters)\n"
      "  --tolerance X          that tolerance in scene units, or X%% of the\n"
      "                         diagonal: p90 distance of strand points to\n"
      "                         their cluster's trajectory and envelope\n"
      "  --fit-report PATH      write every cluster's fit measures (TSV)\n"
      "  --vdb PATH             also write the density as an OpenVDB "
      "FloatGrid\n"
      "                         \"density\" and make the scene use it; "
      "written as\n"
      "                         PATH-XXXXXXXX.vdb (a hash of its bytes)\n"
      "  --voxel SIZE           VDB voxel size (default: from the "
      "clusters)\n"
      "  --follow N             TressFX follow strands per guide "
      "(default: the\n"
      "                         file's header, or 4 where it names none:\n"
      "                         TressFX's own default)\n"
      "  --follow-radius R      their root offset radius (default: the "
      "guides'\n"
      "                         mean root spacing)\n"
      "  --tip-separation F     followers spread (1 + F) times wider at "
      "the tip\n"
      "                         (default 0.5)\n"
      "  --strand-width W       the width of strands whose files give none\n"
      "                         (TressFX, PLY, .data), in the input's units\n"
      "                         (default: a hair fibre's, 1e-3 of the\n"
      "                         hair's bounding-box diagonal)\n"
      "  --control N            trajectory control points (default 8)\n"
      "  --macro-tol T          macro-cluster shape tolerance, relative "
      "to the\n"
      "                         cluster length (default 0.05; 0 = off)\n"
      "  --db PATH              HRIR database to name in the scene "
      "(default: the\n"
      "                         installed PREFIX/share/satf/satf-default.\n"
      "                         hrirdb.exr, or satf-fiber.hrirdb.exr with\n"
      "                         --shading physical; from a build in the\n"
      "                         project, its out/ ones); --database is the\n"
      "                         same\n"
      "  --no-strands           do not write the strands beside the scene "
      "(default:\n"
      "                         SCENE.strands-XXXXXXXX.hair, cyHair, in scene\n"
      "                         coordinates, named by the scene's "
      "\"strands\" key)\n"
      "  --mesh PATH            opaque head mesh (OBJ/PLY) for the scene\n"
      "  --mesh-transform T     where the mesh goes, e.g. 'scale=0.2;\n"
      "                         rotate=1,0,0,-90;translate=0,-2,0' (scaled,\n"
      "                         rotated about the axis by degrees, moved)\n"
      "  --up y|z               the inputs' up axis: z for Blender's and\n"
      "                         other Z-up files, turned upright by\n"
      "                         (x, y, z) -> (x, z, -y) before the\n"
      "                         transforms (default y)\n"
      "  --transform T          where the hair goes, as --mesh-transform\n"
      "  --frames A-B           INPUT is a per-frame pattern "
      "(frame_%%04d.hair):\n"
      "                         frame A defines the clusters, every frame is\n"
      "                         re-fitted onto them as keyframes\n"
      "  --fps F                frame rate of such an animation (default 24)\n"
      "  --memory-budget GB     memory the import may take, estimated at "
      "128 bytes\n"
      "                         a strand point before anything is made "
      "(default 2)\n"
      "  --melanin M            the hair's melanin, 0 (white) to 1 (black),"
      " as\n"
      "                         Cycles' Principled Hair (default 0.6)\n"
      "  --redness R            pheomelanin share of it, 0 to 1 (default 0)\n"
      "  --roughness B          longitudinal roughness, 0 to 1 (default 0.3)\n"
      "  --radial-roughness N   azimuthal roughness, 0 to 1 (default 0.3)\n"
      "  --shading S            kk (the paper's model) or physical (the fibre\n"
      "                         model with a fibre database; default:\n"
      "                         physical when a material option above is\n"
      "                         given, else the scene's, samples/README.md)\n"
      "  --seed N               clustering and placement seed (default "
      "1)\n"
      "  --threads N            threads (0 = all cores)\n"
      "  -q, --quiet            no progress bar or summary\n"
      "  -h, --help             this help\n"
      "\n"
      "Every path the scene names is relative to the scene's folder, so the "
      "scene\n"
      "and its files can be moved together. The side files (VDB, strands) "
      "are\n"
      "named by a hash of their bytes and published with the scene as one "
      "unit:\n"
      "the scene is renamed into place last, then the side files of the "
      "scene it\n"
      "replaced are removed.\n",
      PROG);
}

/* --frames A-B: A < B, both within the frame limits. */
static int parse_frames(const char *val, satf_import_options *o) {
  char tail = 0;
  if (sscanf(val, "%ld-%ld%c", &o->first, &o->last, &tail) != 2 ||
      o->first < -10000000 || o->last > 10000000 || o->last <= o->first) {
    fprintf(stderr, "%s: --frames: expected A-B with A < B, got '%s'\n", PROG,
            val);
    return -1;
  }
  o->sequence = 1;
  return 0;
}

/* One option and its value; 0 when handled, 2 on an error, -1 when it is
 * not an option with a value. */
/* "NAME=a,b,..." with exactly n finite numbers into v; 0 on success. */
static int parse_numbers(const char *text, int n, double *v) {
  for (int k = 0; k < n; k++) {
    char *end = NULL;
    v[k] = strtod(text, &end);
    if (end == text || !isfinite(v[k]))
      return -1;
    text = end;
    if (*text == (k + 1 < n ? ',' : '\0') || (k + 1 == n && *text == ';'))
      text++;
    else
      return -1;
  }
  return 0;
}

/* --mesh-transform or --transform
 * "translate=X,Y,Z;rotate=AX,AY,AZ,DEG;scale=S|SX,SY,SZ", parts in any
 * order; composed as a scene mesh's "transform" (scale, then rotate, then
 * translate) into t, axis, deg and scale. */
static int parse_transform(const char *flag, const char *text, double t[3],
                           double axis[3], double *deg, double scale[3]) {
  char buf[512];
  snprintf(buf, sizeof buf, "%s", text);
  int ok = strlen(text) < sizeof buf && *text;
  for (char *part = strtok(buf, ";"); part && ok; part = strtok(NULL, ";")) {
    double v[4];
    if (!strncmp(part, "translate=", 10) && !parse_numbers(part + 10, 3, v))
      memcpy(t, v, 3 * sizeof *t);
    else if (!strncmp(part, "rotate=", 7) && !parse_numbers(part + 7, 4, v) &&
             v[0] * v[0] + v[1] * v[1] + v[2] * v[2] > 0.0) {
      memcpy(axis, v, 3 * sizeof *axis);
      *deg = v[3];
    } else if (!strncmp(part, "scale=", 6) && !parse_numbers(part + 6, 1, v) &&
               v[0] > 0.0)
      scale[0] = scale[1] = scale[2] = v[0];
    else if (!strncmp(part, "scale=", 6) && !parse_numbers(part + 6, 3, v) &&
             v[0] > 0.0 && v[1] > 0.0 && v[2] > 0.0)
      memcpy(scale, v, 3 * sizeof *scale);
    else
      ok = 0;
  }
  if (!ok)
    fprintf(stderr,
            "%s: %s: expected translate=X,Y,Z;rotate=AX,AY,AZ,DEG;scale=S "
            "(any of them, positive scale, non-zero axis), got '%s'\n",
            PROG, flag, text);
  return ok ? 0 : 2;
}

/* The hair's material (Cycles' Principled Hair meanings). */
static int material_option(satf_cli_args *it, satf_import_options *o) {
  static const char *const names[] = {"--melanin", "--redness", "--roughness",
                                      "--radial-roughness"};
  double *field[] = {&o->melanin, &o->redness, &o->roughness,
                     &o->radial_roughness};
  for (int k = 0; k < 4; k++)
    if (satf_cli_is(it, NULL, names[k]))
      return satf_cli_value_double(it, 0.0, 1.0, field[k]) ? 2 : 0;
  if (satf_cli_is(it, NULL, "--shading")) {
    const char *val;
    if (satf_cli_value(it, &val))
      return 2;
    if (!strcmp(val, "kk") || !strcmp(val, "physical")) {
      o->shading = val[0] == 'k' ? SATF_MATERIAL_KK : SATF_MATERIAL_PHYSICAL;
      return 0;
    }
    fprintf(stderr, "%s: --shading '%s': kk or physical\n", PROG, val);
    return 2;
  }
  return -1;
}

static int value_option(satf_cli_args *it, satf_import_options *o) {
  const char *val;
  if (satf_cli_is(it, "-o", "--output"))
    return satf_cli_value(it, &o->output) ? 2 : 0;
  if (satf_cli_is(it, NULL, "--vdb"))
    return satf_cli_value(it, &o->vdb) ? 2 : 0;
  if (satf_cli_is(it, NULL, "--mesh"))
    return satf_cli_value(it, &o->mesh) ? 2 : 0;
  if (satf_cli_is(it, NULL, "--mesh-transform"))
    return satf_cli_value(it, &val)
               ? 2
               : parse_transform("--mesh-transform", val, o->mesh_translate,
                                 o->mesh_axis, &o->mesh_angle_deg,
                                 o->mesh_scale);
  if (satf_cli_is(it, NULL, "--transform"))
    return satf_cli_value(it, &val)
               ? 2
               : parse_transform("--transform", val, o->hair_translate,
                                 o->hair_axis, &o->hair_angle_deg,
                                 o->hair_scale);
  if (satf_cli_is(it, NULL, "--up")) {
    if (satf_cli_value(it, &val))
      return 2;
    if ((val[0] == 'y' || val[0] == 'z') && !val[1]) {
      o->up_z = val[0] == 'z';
      return 0;
    }
    fprintf(stderr, "%s: --up '%s': y (the default) or z (Blender's)\n", PROG,
            val);
    return 2;
  }
  if (satf_cli_is(it, NULL, "--db") || satf_cli_is(it, NULL, "--database"))
    return satf_cli_value(it, &o->database) ? 2 : 0;
  if (satf_cli_is(it, NULL, "--clusters"))
    return satf_cli_value_int(it, 1, SATF_IMPORT_MAX_CLUSTERS, &o->clusters)
               ? 2
               : 0;
  if (satf_cli_is(it, NULL, "--quality")) {
    if (satf_cli_value(it, &val))
      return 2;
    if (!strcmp(val, "draft") || !strcmp(val, "default") ||
        !strcmp(val, "high")) {
      o->quality = val[0] == 'd' && val[1] == 'r' ? SATF_IMPORT_QUALITY_DRAFT
                   : val[0] == 'h'                ? SATF_IMPORT_QUALITY_HIGH
                                                  : SATF_IMPORT_QUALITY_DEFAULT;
      return 0;
    }
    fprintf(stderr, "%s: --quality '%s': draft, default or high\n", PROG, val);
    return 2;
  }
  if (satf_cli_is(it, NULL, "--tolerance")) {
    if (satf_cli_value(it, &val))
      return 2;
    size_t len = strlen(val);
    int pct = len > 0 && val[len - 1] == '%';
    char num[64];
    snprintf(num, sizeof num, "%.*s", (int)(pct ? len - 1 : len), val);
    if (satf_cli_double(PROG, "--tolerance", num, pct ? 1e-4 : 1e-9,
                        pct ? 100.0 : 1e6, &o->tolerance))
      return 2;
    if (pct)
      o->tolerance = -o->tolerance / 100.0; /* a fraction of the diagonal */
    return 0;
  }
  if (satf_cli_is(it, NULL, "--fit-report"))
    return satf_cli_value(it, &o->fit_report) ? 2 : 0;
  if (satf_cli_is(it, NULL, "--follow"))
    return satf_cli_value_int(it, 0, SATF_STRANDS_MAX_FOLLOW, &o->follow) ? 2
                                                                          : 0;
  if (satf_cli_is(it, NULL, "--frames"))
    return satf_cli_value(it, &val) || parse_frames(val, o) ? 2 : 0;
  if (satf_cli_is(it, NULL, "--fps"))
    return satf_cli_value_double(it, 0.001, 1000.0, &o->fps) ? 2 : 0;
  if (satf_cli_is(it, NULL, "--control"))
    return satf_cli_value_int(it, 2, 64, &o->control) ? 2 : 0;
  if (satf_cli_is(it, NULL, "--threads"))
    return satf_cli_value_int(it, 0, 256, &o->threads) ? 2 : 0;
  if (satf_cli_is(it, NULL, "--voxel"))
    return satf_cli_value_double(it, 1e-5, 1e6, &o->voxel) ? 2 : 0;
  if (satf_cli_is(it, NULL, "--follow-radius"))
    return satf_cli_value_double(it, 0.0, 1e6, &o->follow_radius) ? 2 : 0;
  if (satf_cli_is(it, NULL, "--tip-separation"))
    return satf_cli_value_double(it, 0.0, 100.0, &o->tip_separation) ? 2 : 0;
  if (satf_cli_is(it, NULL, "--strand-width"))
    return satf_cli_value_double(it, 1e-30, 1e30, &o->strand_width) ? 2 : 0;
  if (satf_cli_is(it, NULL, "--macro-tol"))
    return satf_cli_value_double(it, 0.0, 1.0, &o->macro_tol) ? 2 : 0;
  if (satf_cli_is(it, NULL, "--memory-budget")) {
    double gb;
    if (satf_cli_value_double(it, 0.001, 1e6, &gb))
      return 2;
    o->memory_budget = gb * 1e9;
    return 0;
  }
  if (satf_cli_is(it, NULL, "--seed"))
    return satf_cli_value_u64(it, &o->seed) ? 2 : 0;
  return material_option(it, o);
}

/* A sequence: one INPUT pattern with one integer conversion and no other
 * %, and no --vdb. */
static int check_sequence(satf_import_options *o) {
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
  return 0;
}

/* No output may overwrite an input or another output. */
static int check_files(const satf_import_options *o) {
  satf_file_role files[SATF_IMPORT_MAX_INPUTS + 4] = {{"-o", o->output, 1},
                                                      {"--vdb", o->vdb, 1},
                                                      {"--mesh", o->mesh, 0},
                                                      {"--db", o->database, 0}};
  int n = 4;
  for (int i = 0; i < o->n_inputs && !o->sequence; i++)
    files[n++] = (satf_file_role){"the input", o->inputs[i], 0};
  satf_error err;
  if (satf_check_distinct_files(files, n, &err) != SATF_OK ||
      satf_check_output_extension("-o", o->output, ".json", "a JSON scene",
                                  &err) ||
      satf_check_output_extension("--vdb", o->vdb, ".vdb", "an OpenVDB grid",
                                  &err)) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    return 2;
  }
  return 0;
}

/* The installed default database for the shading (satf_data_dir), else
 * the one the project's main command builds (scripts/main.sh):
 * PROJECT/out/satf-default.hrirdb.exr (Phong records) or,
 * for --shading physical, PROJECT/out/satf-fiber.hrirdb.exr, where this
 * program runs as PROJECT/BUILD/bin/satf-import. NULL when it is not
 * there. */
static const char *default_database(int physical) {
  static char path[PATH_MAX];
  if (satf_default_database(physical, path, sizeof path))
    return path; /* installed (satf_data_dir) */
  char exe[PATH_MAX];
  ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0)
    return NULL;
  exe[n] = '\0';
  for (int up = 0; up < 3; up++) { /* satf-import, bin, BUILD */
    char *slash = strrchr(exe, '/');
    if (!slash || slash == exe)
      return NULL;
    *slash = '\0';
  }
  struct stat sb;
  int len = snprintf(path, sizeof path, "%s/out/satf-%s.hrirdb.exr", exe,
                     physical ? "fiber" : "default");
  return len > 0 && len < (int)sizeof path && stat(path, &sb) == 0 &&
                 S_ISREG(sb.st_mode)
             ? path
             : NULL;
}

/* A --db that is not a readable file would only fail at render time. */
static int check_database(const satf_import_options *o) {
  struct stat sb;
  if (!o->database)
    return 0;
  if (stat(o->database, &sb) != 0 || !S_ISREG(sb.st_mode) ||
      access(o->database, R_OK) != 0) {
    fprintf(stderr, "%s: --db %s: %s\n", PROG, o->database,
            stat(o->database, &sb) != 0 ? strerror(errno)
                                        : "not a readable regular file");
    return 2;
  }
  return 0;
}

/* 0: run; 1: done (--help); 2: a usage error (printed). */
static int parse_args(int argc, char **argv, satf_import_options *o) {
  *o = satf_import_options_default();
  satf_cli_args it;
  satf_cli_begin(&it, PROG, argc, argv);
  while (satf_cli_next(&it)) {
    int rc;
    if (satf_cli_is(&it, "-h", "--help")) {
      usage(stdout);
      return 1;
    } else if ((rc = value_option(&it, o)) >= 0) {
      if (rc)
        return rc;
    } else if (satf_cli_is(&it, "-q", "--quiet")) {
      o->quiet = 1;
    } else if (satf_cli_is(&it, NULL, "--no-strands")) {
      o->no_strands = 1;
    } else if (!satf_cli_positional(&it) && strcmp(it.arg, "-") != 0) {
      return satf_cli_unknown(&it);
    } else if (o->n_inputs < SATF_IMPORT_MAX_INPUTS) {
      o->inputs[o->n_inputs++] = it.arg;
    } else {
      fprintf(stderr, "%s: at most 64 input files\n", PROG);
      return 2;
    }
  }
  if (o->sequence && check_sequence(o))
    return 2;
  if (o->n_inputs == 0 || !o->output) {
    fprintf(stderr, "%s: need INPUT files and -o SCENE.json (see --help)\n",
            PROG);
    return 2;
  }
  /* The material options are the fibre model's: a user who gives the
   * hair's melanin expects to see it, and the paper's kk model has no
   * melanin (its colours are f_dif and f_spe), so they choose the physical
   * shading unless --shading says otherwise. */
  int material = o->melanin >= 0.0 || o->redness >= 0.0 ||
                 o->roughness >= 0.0 || o->radial_roughness >= 0.0;
  if (material && o->shading < 0) {
    o->shading = SATF_MATERIAL_PHYSICAL;
    if (!o->quiet)
      fprintf(stderr,
              "%s: the material options are the physical shading's: the "
              "scene shades physical (--shading kk keeps the paper's "
              "model, which does not use them)\n",
              PROG);
  } else if (material && o->shading == SATF_MATERIAL_KK) {
    fprintf(stderr,
            "%s: warning: --shading kk does not use the material options "
            "(they are written to the scene for --shading physical)\n",
            PROG);
  }
  if (!o->database)
    o->database = default_database(o->shading == SATF_MATERIAL_PHYSICAL);
  return check_database(o) ? 2 : check_files(o);
}

int main(int argc, char **argv) {
  satf_import_options o;
  int rc = parse_args(argc, argv, &o);
  if (rc)
    return rc == 1 ? 0 : rc;
  satf_import_result result;
  satf_error err;
  if (satf_import_run(&o, &result, &err) != SATF_OK) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    return 1;
  }
  if (!o.quiet)
    satf_import_print_summary(stdout, PROG, &o, &result);
  return 0;
}
