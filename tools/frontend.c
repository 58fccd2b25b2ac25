/* frontend.c - see frontend.h: loading a scene with its database (and the
 * fibre database the physical shading takes), the memory budget, and the
 * renderer made from them. frontend_strands.c draws the source strands,
 * frontend_flags.c parses the shared flags, frontend_bench.c runs the
 * Table 1 benchmark. */
#define _POSIX_C_SOURCE 200809L
#include "frontend.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "satf/common.h"
#include "satf/math.h"

/* The set-up bar appears only once the set-up has taken a second: the
 * samples set up in a fraction of one, and a line each would clutter
 * batch logs and the Table 1 rows. */
typedef struct setup_bar {
  satf_progress prog;
  int shown;
} setup_bar;

static void setup_progress(void *ctx, size_t done, size_t total) {
  setup_bar *b = ctx;
  if (!b->shown && satf_now_seconds() - b->prog.start < 1.0)
    return;
  b->shown = 1;
  satf_progress_update(&b->prog, done, total);
}

satf_status satf_frontend_create_renderer(const satf_frontend *fe, int width,
                                          int height, int threads, int quiet,
                                          satf_renderer **out,
                                          satf_error *err) {
  setup_bar bar = {.shown = 0};
  satf_progress_begin(&bar.prog, stderr, "set-up", "clusters", 1, quiet);
  satf_status st =
      satf_renderer_create_progress(fe->scene, fe->db, width, height, threads,
                                    setup_progress, &bar, out, err);
  if (bar.shown)
    satf_progress_end(&bar.prog);
  if (st == SATF_OK && fe->sparse_strands >= 0 &&
      (st = satf_renderer_set_sparse_strands(*out, fe->sparse_strands, err)) !=
          SATF_OK) {
    satf_renderer_destroy(*out);
    *out = NULL;
  }
  return st;
}

/* The installed default database's path, malloc'ed; NULL when none. */
static char *installed_database(void) {
  char path[PATH_MAX];
  if (!satf_default_database(0, path, sizeof path))
    return NULL;
  char *copy = malloc(strlen(path) + 1);
  if (copy)
    strcpy(copy, path);
  return copy;
}

/* Half the machine's physical memory (2 GB when it cannot be read). */
static double default_budget(void) {
  long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && size > 0 ? 0.5 * (double)pages * (double)size : 2e9;
}

/* SATF_ERR_ARGUMENT and a message naming the largest part where the
 * estimate of scene_path's render (*need) is over budget. */
static satf_status over_budget(const satf_scene *scene, const char *scene_path,
                               const satf_render_memory_options *opt,
                               double budget, satf_render_memory *need,
                               satf_error *err) {
  satf_render_memory_estimate(scene, opt, need);
  if (!(need->total > budget))
    return SATF_OK;
  /* the database's parts once it is known (satf_frontend_check_memory) */
  char known[128] = "", path[96] = "";
  if (opt->strand_points > 0)
    snprintf(path, sizeof path, ", %.2f GB for the %zu points of --strands",
             need->strand_path / 1e9, opt->strand_points);
  if (opt->db)
    snprintf(known, sizeof known,
             ", %.2f GB for the database, %.2f GB for the GPU's maps",
             need->database / 1e9, need->gpu_maps / 1e9);
  return satf_error_set(
      err, SATF_ERR_ARGUMENT,
      "%s: rendering it would take about %.2f GB, over the memory budget "
      "of %.2f GB; the most is %s (%.2f GB for %llu HSVs, %.2f GB for %llu "
      "strands, %.2f GB for %ldx%ld pixels, %.2f GB of VDB density%s%s): "
      "use fewer clusters, layers, st or su, fewer strands, a smaller "
      "--size, a coarser VDB%s, or raise the budget with --memory-budget GB",
      scene_path, need->total / 1e9, budget / 1e9,
      satf_render_memory_largest(need), need->hsvs / 1e9,
      (unsigned long long)satf_scene_hsv_count(scene), need->strands / 1e9,
      (unsigned long long)satf_scene_strand_count(scene), need->pixels / 1e9,
      opt->width, opt->height, need->vdb / 1e9, known, path,
      need->gpu_maps > 0.0 ? " or the CPU's maps (--maps cpu)" : "");
}

satf_status satf_frontend_load(const char *prog, const char *scene_path,
                               const char *db_path, double budget, long *width,
                               long *height, satf_frontend *fe) {
  memset(fe, 0, sizeof *fe);
  satf_error err;
  satf_error_clear(&err);
  satf_status st = satf_scene_load(scene_path, &fe->scene, &err);
  fe->scene_path = scene_path;
  fe->budget = budget > 0.0 ? budget : default_budget();
  long w = *width ? *width : st == SATF_OK ? fe->scene->image.width : 0;
  long h = *width ? *height : st == SATF_OK ? fe->scene->image.height : 0;
  /* before the database is read: a lower bound (neither the database nor
   * the maps counted, and every cluster the renderer may draw as strands
   * at the cheaper of its two ways), which satf_frontend_check_memory
   * completes */
  satf_render_memory_options opt = satf_render_memory_options_default();
  opt.width = w;
  opt.height = h;
  opt.sparse_strands = SATF_SPARSE_STRANDS_MAX;
  satf_render_memory need;
  if (st == SATF_OK)
    st = over_budget(fe->scene, scene_path, &opt, fe->budget, &need, &err);
  if (st == SATF_OK) {
    for (int i = 0; i < satf_scene_warning_count(fe->scene); i++)
      fprintf(stderr, "%s: warning: %s\n", prog,
              satf_scene_warning(fe->scene, i));
    const char *db = db_path ? db_path : fe->scene->database;
    /* neither names one: the installed default (satf_data_dir), whose
     * fibre database lies beside it for the physical shading */
    if (!db)
      db = fe->db_path_owned = installed_database();
    if (!db)
      st = satf_error_set(&err, SATF_ERR_ARGUMENT,
                          "%s: no database: give --db DB.exr or a "
                          "\"database\" key in the scene, or install the "
                          "default ones (satf-build --install-default)",
                          scene_path);
    else
      st = satf_db_read(db, &fe->db, &err);
    fe->db_path = db;
    fe->db_from_scene = !db_path;
  }
  if (st != SATF_OK) {
    fprintf(stderr, "%s: %s\n", prog, err.message);
    satf_frontend_free(fe);
    return st;
  }
  if (*width == 0) {
    *width = fe->scene->image.width;
    *height = fe->scene->image.height;
  }
  return SATF_OK;
}

satf_status satf_frontend_check_memory(const char *prog, satf_frontend *fe,
                                       long width, long height,
                                       satf_maps_mode maps) {
  satf_error err;
  satf_error_clear(&err);
  satf_render_memory_options opt = satf_render_memory_options_default();
  opt.width = width;
  opt.height = height;
  opt.db = fe->db;
  opt.maps = maps;
  if (fe->sparse_strands >= 0)
    opt.sparse_strands = fe->sparse_strands;
  if (fe->strands)
    opt.strand_points = satf_strand_set_point_count(fe->strands);
  satf_render_memory need;
  satf_status st =
      over_budget(fe->scene, fe->scene_path, &opt, fe->budget, &need, &err);
  fe->memory_estimate = need.total;
  if (st != SATF_OK)
    fprintf(stderr, "%s: %s\n", prog, err.message);
  return st;
}

void satf_frontend_apply(satf_renderer *r, const satf_scene_effects *off,
                         int composite) {
  satf_scene_effects *e = satf_renderer_effects(r);
  e->satf &= off->satf;
  e->secondary_highlight &= off->secondary_highlight;
  e->self_shadow &= off->self_shadow;
  e->cluster_shadows &= off->cluster_shadows;
  satf_renderer_set_composite(r, (satf_composite)composite);
}

void satf_frontend_maps_note(const char *prog, const satf_renderer *r) {
  if (r && satf_renderer_maps_note(r)[0])
    fprintf(stderr, "%s: the maps built on the CPU: the GPU's: %s\n", prog,
            satf_renderer_maps_note(r));
}

void satf_frontend_free(satf_frontend *fe) {
  satf_strand_set_destroy(fe->strands);
  satf_db_destroy(fe->db);
  satf_scene_destroy(fe->scene);
  free(fe->db_path_owned);
  memset(fe, 0, sizeof *fe);
}

int satf_frontend_budget_flag(satf_cli_args *it, double *bytes) {
  if (!satf_cli_is(it, NULL, "--memory-budget"))
    return 0;
  double gb = 0.0;
  if (satf_cli_value_double(it, 0.001, 1e6, &gb))
    return -1;
  *bytes = gb * 1e9;
  return 1;
}

const char *const satf_frontend_budget_help =
    "  --memory-budget GB   memory the renderer may take, estimated from the\n"
    "                       scene's HSVs, strands and image size, the\n"
    "                       database and where the maps are built, before\n"
    "                       anything is built (default: half the\n"
    "                       machine's memory)\n";

/* The fibre database satf-build makes beside a Phong one (scripts/main.sh
 * writes out/satf-default.hrirdb.exr and out/satf-fiber.hrirdb.exr), for a
 * scene whose own "database" is the Phong one: NULL when there is none. */
static char *fiber_beside(const char *phong) {
  static const char name[] = "satf-fiber.hrirdb.exr";
  const char *slash = strrchr(phong, '/');
  size_t dir = slash ? (size_t)(slash - phong) + 1 : 0;
  char *path = malloc(dir + sizeof name);
  if (!path)
    return NULL;
  memcpy(path, phong, dir);
  memcpy(path + dir, name, sizeof name);
  struct stat sb, pb;
  if (stat(path, &sb) != 0 || !S_ISREG(sb.st_mode) ||
      (stat(phong, &pb) == 0 && pb.st_dev == sb.st_dev &&
       pb.st_ino == sb.st_ino)) {
    free(path);
    return NULL;
  }
  return path;
}

satf_status satf_frontend_set_shading(const char *prog, satf_frontend *fe,
                                      int model) {
  if (model >= 0)
    fe->scene->material.model = (satf_material_model)model;
  if (fe->scene->material.model != SATF_MATERIAL_PHYSICAL ||
      !fe->scene->effects.satf || satf_db_kind(fe->db) == SATF_RECORD_FIBER)
    return SATF_OK;
  /* the scene names the Phong database and the fibre one lies beside it:
   * physical shading takes that one (a --db given is used as given) */
  char *fiber = fe->db_from_scene ? fiber_beside(fe->db_path) : NULL;
  satf_db *db = NULL;
  satf_error err;
  satf_status read = fiber ? satf_db_read(fiber, &db, &err) : SATF_OK;
  if (read != SATF_OK) /* there but unreadable: say why it was not taken */
    fprintf(stderr, "%s: warning: %s\n", prog, err.message);
  if (fiber && read == SATF_OK && satf_db_kind(db) == SATF_RECORD_FIBER) {
    fprintf(stderr, "%s: the physical shading takes the fibre database %s\n",
            prog, fiber);
    satf_db_destroy(fe->db);
    fe->db = db;
    free(fe->db_path_owned);
    fe->db_path = fe->db_path_owned = fiber;
    return SATF_OK;
  }
  satf_db_destroy(db);
  free(fiber);
  fprintf(stderr,
          "%s: %s: the physical shading needs a fibre database (satf-build "
          "--kind fiber, e.g. out/satf-fiber.hrirdb.exr); %s holds Phong "
          "records (give --db, or --shading kk)\n",
          prog, fe->scene->name ? fe->scene->name : "scene", fe->db_path);
  return SATF_ERR_INCOMPATIBLE;
}
