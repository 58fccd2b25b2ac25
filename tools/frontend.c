/* frontend.c - see frontend.h. */
#define _POSIX_C_SOURCE 200809L
#include "frontend.h"

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

/* Half the machine's physical memory (2 GB when it cannot be read). */
static double default_budget(void) {
  long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && size > 0 ? 0.5 * (double)pages * (double)size : 2e9;
}

satf_status satf_frontend_load(const char *prog, const char *scene_path,
                               const char *db_path, double budget, long *width,
                               long *height, satf_frontend *fe) {
  memset(fe, 0, sizeof *fe);
  satf_error err;
  satf_error_clear(&err);
  satf_status st = satf_scene_load(scene_path, &fe->scene, &err);
  if (!(budget > 0.0))
    budget = default_budget();
  long w = *width ? *width : st == SATF_OK ? fe->scene->image.width : 0;
  long h = *width ? *height : st == SATF_OK ? fe->scene->image.height : 0;
  satf_render_memory need = {0};
  if (st == SATF_OK)
    satf_render_memory_estimate(fe->scene, w, h, &need);
  if (st == SATF_OK && need.total > budget)
    st = satf_error_set(
        &err, SATF_ERR_ARGUMENT,
        "%s: rendering it would take about %.2f GB, over the memory budget "
        "of %.2f GB; the most is %s (%.2f GB for %llu HSVs, %.2f GB for %llu "
        "strands, %.2f GB for %ldx%ld pixels, %.2f GB of VDB density): use "
        "fewer clusters, layers, st or su, fewer strands, a smaller --size or "
        "a coarser VDB, or raise the budget with --memory-budget GB",
        scene_path, need.total / 1e9, budget / 1e9,
        satf_render_memory_largest(&need), need.hsvs / 1e9,
        (unsigned long long)satf_scene_hsv_count(fe->scene), need.strands / 1e9,
        (unsigned long long)satf_scene_strand_count(fe->scene),
        need.pixels / 1e9, w, h, need.vdb / 1e9);
  if (st == SATF_OK) {
    for (int i = 0; i < satf_scene_warning_count(fe->scene); i++)
      fprintf(stderr, "%s: warning: %s\n", prog,
              satf_scene_warning(fe->scene, i));
    const char *db = db_path ? db_path : fe->scene->database;
    if (!db)
      st = satf_error_set(&err, SATF_ERR_ARGUMENT,
                          "%s: no database: give --db DB.exr or a "
                          "\"database\" key in the scene",
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

void satf_frontend_apply(satf_renderer *r, const satf_scene_effects *off,
                         int composite) {
  satf_scene_effects *e = satf_renderer_effects(r);
  e->satf &= off->satf;
  e->secondary_highlight &= off->secondary_highlight;
  e->self_shadow &= off->self_shadow;
  e->cluster_shadows &= off->cluster_shadows;
  satf_renderer_set_composite(r, (satf_composite)composite);
}

void satf_frontend_free(satf_frontend *fe) {
  satf_strand_set_destroy(fe->strands);
  satf_db_destroy(fe->db);
  satf_scene_destroy(fe->scene);
  free(fe->db_path_owned);
  memset(fe, 0, sizeof *fe);
}

satf_status satf_frontend_load_strands(const char *prog, satf_frontend *fe) {
  satf_error err;
  satf_error_clear(&err);
  satf_status st;
  if (!fe->scene->strands_file)
    st = satf_error_set(&err, SATF_ERR_ARGUMENT,
                        "%s: --strands: the scene has no source strands (no "
                        "\"strands\" key naming a .hair file; satf-import "
                        "writes one beside the scenes it makes)",
                        fe->scene->name ? fe->scene->name : "scene");
  else
    st = satf_hair_read(fe->scene->strands_file, &fe->strands, &err);
  if (st != SATF_OK)
    fprintf(stderr, "%s: %s\n", prog, err.message);
  return st;
}

static float curve_mean(const satf_scene_curve *c) {
  double sum = 0.0;
  for (int i = 0; i < c->count; i++)
    sum += c->values[i];
  return c->count > 0 ? (float)(sum / c->count) : 0.0f;
}

static int float_less(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

/* The strand diameter the clusters' density assumes (what satf-import
 * estimates from the strands' spacing: "strand_width" in units of the
 * cluster radius sqrt(mean a * mean b), world sigma = width * radius / 2,
 * import_density.c), the median over the placed clusters; 0 if none. */
static float density_strand_width(const satf_scene *scene) {
  int n = 0;
  for (int m = 0; m < scene->n_macro_clusters; m++)
    n += scene->macro_clusters[m].n_instances;
  float *w = malloc((size_t)(n > 0 ? n : 1) * sizeof(float));
  if (!w)
    return 0.0f;
  int k = 0;
  for (int m = 0; m < scene->n_macro_clusters; m++) {
    const satf_scene_cluster *c = &scene->macro_clusters[m].prototype;
    if (c->density.type != SATF_SCENE_DENSITY_PROCEDURAL)
      continue;
    float radius = sqrtf(curve_mean(&c->a) * curve_mean(&c->b));
    for (int i = 0; i < scene->macro_clusters[m].n_instances; i++) {
      const float *t = scene->macro_clusters[m].instances[i].m;
      float det = t[0] * (t[5] * t[10] - t[6] * t[9]) -
                  t[1] * (t[4] * t[10] - t[6] * t[8]) +
                  t[2] * (t[4] * t[9] - t[5] * t[8]);
      w[k++] = c->density.strand_width * radius * cbrtf(fabsf(det));
    }
  }
  qsort(w, (size_t)k, sizeof *w, float_less);
  float median = k > 0 ? w[k / 2] : 0.0f;
  free(w);
  return median;
}

satf_status satf_frontend_apply_strands(satf_renderer *r,
                                        const satf_frontend *fe,
                                        satf_error *err) {
  const satf_strand_set *s = fe->strands;
  if (!s)
    return SATF_OK;
  int n = satf_strand_set_count(s);
  size_t np = satf_strand_set_point_count(s);
  int thick = n > 0 && satf_strand_set_thickness(s, 0) != NULL;
  /* the renderer takes plain arrays (it does not depend on satf_import) */
  int *counts = malloc((size_t)(n > 0 ? n : 1) * sizeof(int));
  float *xyz = malloc((np > 0 ? np : 1) * 3 * sizeof(float));
  float *width = malloc((np > 0 ? np : 1) * sizeof(float));
  if (!counts || !xyz || !width) {
    free(counts);
    free(xyz);
    free(width);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  size_t at = 0;
  for (int i = 0; i < n; i++) {
    const float *p = satf_strand_set_strand(s, i, &counts[i]);
    const float *t = satf_strand_set_thickness(s, i);
    memcpy(xyz + 3 * at, p, 3 * (size_t)counts[i] * sizeof(float));
    for (int j = 0; j < counts[i]; j++)
      width[at + (size_t)j] = fe->strand_width > 0.0f ? fe->strand_width
                              : thick && t            ? t[j]
                                                      : 0.0f;
    at += (size_t)counts[i];
  }
  /* --strand-width density, or no thickness: the width the clusters'
   * density assumes */
  int have = fe->strand_width > 0.0f || (thick && fe->strand_width == 0.0f);
  float assumed = have ? 0.0f : density_strand_width(fe->scene);
  if (!have && !(assumed > 0.0f)) {
    free(counts);
    free(xyz);
    free(width);
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: no strand width: the file has no thickness "
                          "and no cluster has a procedural density to take "
                          "one from (give --strand-width W)",
                          fe->scene->strands_file);
  }
  satf_status st = satf_renderer_set_strands(r, n, counts, xyz,
                                             have ? width : NULL, assumed, err);
  if (st != SATF_OK) {
    satf_error why = *err; /* the message is rewritten from a copy */
    st = satf_error_set(err, st, "%s: %s%s", fe->scene->strands_file,
                        why.message, have ? "" : " (give --strand-width)");
  }
  free(counts);
  free(xyz);
  free(width);
  return st;
}

int satf_frontend_strand_flag(satf_cli_args *it, int *on, float *width) {
  if (satf_cli_is(it, NULL, "--strands")) {
    *on = 1;
    return 1;
  }
  if (!satf_cli_is(it, NULL, "--strand-width"))
    return 0;
  const char *val;
  if (satf_cli_value(it, &val))
    return -1;
  if (!strcmp(val, "density")) {
    *width = -1.0f; /* satf_frontend_apply_strands takes the clusters' */
    return 1;
  }
  char *end;
  double w = strtod(val, &end);
  if (end == val || *end || !(w > 0.0 && w < 1e9)) {
    fprintf(stderr,
            "%s: --strand-width: expected a width in scene units (> 0) or "
            "'density', got '%s'\n",
            it->prog, val);
    return -1;
  }
  *width = (float)w;
  return 1;
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
    "                       scene's HSVs, strands and image size before\n"
    "                       anything is built (default: half the\n"
    "                       machine's memory)\n";

const char *const satf_frontend_strand_help =
    "  --strands            draw the scene's source strands (its \"strands\"\n"
    "                       .hair file) instead of the clusters: the\n"
    "                       reference the clusters approximate, same lights,\n"
    "                       material, shading and shadows (slow)\n"
    "  --strand-width W     with --strands: every strand W scene units wide\n"
    "                       (default: the file's thickness); 'density': the\n"
    "                       width the clusters' density assumes (median of\n"
    "                       strand_width x cluster radius)\n";

const char *const satf_frontend_shading_help =
    "  --shading MODEL      kk: the paper's Kajiya-Kay lighting of the maps;\n"
    "                       physical: the fibre model (Cycles' Principled\n"
    "                       Hair) with a fibre database (satf-build --kind\n"
    "                       fiber; satf-fiber.hrirdb.exr beside the scene's\n"
    "                       Phong database is taken when there is no --db);\n"
    "                       default: the scene's material \"model\"\n";

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

const char *const satf_frontend_sparse_help =
    "  --sparse-strands N   clusters of at most N strands (satf-import's\n"
    "                       \"tracks\"), and tufts of short strands (fur),\n"
    "                       are drawn as those strands, with the\n"
    "                       clusters; 0: every cluster as a cluster\n"
    "                       (default 8)\n";

int satf_frontend_sparse_flag(satf_cli_args *it, int *max_strands) {
  if (!satf_cli_is(it, NULL, "--sparse-strands"))
    return 0;
  long n;
  if (satf_cli_value_int(it, 0, SATF_SPARSE_STRANDS_MAX, &n))
    return -1;
  *max_strands = (int)n;
  return 1;
}

int satf_frontend_shading_flag(satf_cli_args *it, int *model) {
  if (!satf_cli_is(it, NULL, "--shading"))
    return 0;
  const char *val;
  if (satf_cli_value(it, &val))
    return -1;
  if (!strcmp(val, "kk") || !strcmp(val, "physical")) {
    *model = val[0] == 'k' ? SATF_MATERIAL_KK : SATF_MATERIAL_PHYSICAL;
    return 1;
  }
  fprintf(stderr, "%s: --shading: expected kk or physical, got '%s'\n",
          it->prog, val);
  return -1;
}

const char *const satf_frontend_effect_help =
    "  --no-satf            Fig. 4a's baseline, Scheuermann 2004 (paper 002):\n"
    "                       shell layers as textured patches, wrapped\n"
    "                       diffuse, two shifted highlights, ambient\n"
    "                       occlusion, depth-sorted passes; no database\n"
    "  --no-secondary       no secondary highlight (Fig. 4b)\n"
    "  --no-self-shadow     no s-map self-shadowing (Fig. 4c); with\n"
    "                       --no-satf, no ambient occlusion\n"
    "  --no-cluster-shadows no deep-opacity shadows between clusters\n"
    "  --composite MODE     exact: every fragment of a pixel sorted by depth;\n"
    "                       ordered: clusters far to near, shells back to\n"
    "                       front by drawing order (faster)\n";

int satf_frontend_effect_flag(const char *arg, satf_scene_effects *e) {
  if (!strcmp(arg, "--no-satf"))
    e->satf = 0;
  else if (!strcmp(arg, "--no-secondary"))
    e->secondary_highlight = 0;
  else if (!strcmp(arg, "--no-self-shadow"))
    e->self_shadow = 0;
  else if (!strcmp(arg, "--no-cluster-shadows"))
    e->cluster_shadows = 0;
  else
    return 0;
  return 1;
}

int satf_frontend_composite(const char *value) {
  if (value && !strcmp(value, "exact"))
    return SATF_COMPOSITE_EXACT;
  if (value && !strcmp(value, "ordered"))
    return SATF_COMPOSITE_ORDERED;
  return -1;
}

void satf_frontend_table_header(FILE *out) {
  fprintf(out, "%-16s %4s %4s %6s %6s %7s %7s %7s %7s %7s %7s\n", "scene", "C#",
          "L#", "S#(K)", "H#(K)", "I ms", "C ms", "M ms", "L ms", "S ms",
          "FPS");
}

void satf_frontend_table_row(FILE *out, const char *name,
                             const satf_render_stats *s,
                             const satf_frame_timing *m, double fps) {
  fprintf(
      out, "%-16s %4ld %4ld %6.1f %6.1f %7.1f %7.1f %7.1f %7.1f %7.1f %7.1f\n",
      name, s->clusters, s->layers, s->strands / 1000.0, s->hsvs / 1000.0,
      m->index_ms, m->maps_ms, m->upload_ms, m->lighting_ms, m->shadow_ms, fps);
}

satf_status satf_frontend_frame_range(const satf_scene *scene, const char *text,
                                      int *first, int *last, satf_error *err) {
  char tail = 0;
  if (!strcmp(text, "all")) {
    satf_scene_frame_range(scene, first, last);
  } else if (sscanf(text, "%d-%d%c", first, last, &tail) != 2) {
    if (sscanf(text, "%d%c", first, &tail) != 1)
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "--frames: expected A-B, N or all, got '%s'", text);
    *last = *first;
  }
  /* Frames outside the scene's own would render a held pose under names
   * that no frame of the scene has (f_-001), so they are refused. */
  int lo = 0, hi = 0;
  int animated = satf_scene_frame_range(scene, &lo, &hi);
  if (*first > *last || *first < 0 || (animated && (*first < lo || *last > hi)))
    return animated ? satf_error_set(err, SATF_ERR_ARGUMENT,
                                     "--frames: '%s' is not a range A-B with "
                                     "A <= B within the scene's frames %d-%d",
                                     text, lo, hi)
                    : satf_error_set(err, SATF_ERR_ARGUMENT,
                                     "--frames: '%s' is not a range A-B with "
                                     "0 <= A <= B",
                                     text);
  return SATF_OK;
}

/* Rotates the eye about the up axis through the target (Rodrigues). */
static void orbit(satf_scene_camera *cam, const satf_scene_camera *start,
                  float angle) {
  float v[3], kx[3];
  for (int a = 0; a < 3; a++)
    v[a] = start->position[a] - start->target[a];
  float c = cosf(angle), s = sinf(angle);
  float kv = satf_dot3f(start->up, v);
  satf_cross3f(start->up, v, kx);
  for (int a = 0; a < 3; a++)
    cam->position[a] =
        start->target[a] + v[a] * c + kx[a] * s + start->up[a] * kv * (1 - c);
}

void satf_frontend_walk_begin(satf_frontend_walk *w, satf_renderer *r,
                              const satf_scene *scene, long frames) {
  memset(w, 0, sizeof *w);
  w->r = r;
  w->scene = scene;
  w->start = *satf_renderer_camera(r);
  w->frames = frames > 0 ? frames : 1;
  w->animated = satf_scene_frame_range(scene, &w->first, &w->last);
}

satf_status satf_frontend_walk_step(satf_frontend_walk *w, long f,
                                    satf_error *err) {
  if (!w->animated) {
    orbit(satf_renderer_camera(w->r), &w->start,
          SATF_TWO_PI_F * (float)f / (float)w->frames);
    return SATF_OK;
  }
  /* play the animation: moving clusters are rebuilt */
  satf_scene *next = NULL;
  double frame = w->first + (double)(f % (w->last - w->first + 1));
  satf_status st = satf_scene_at_frame(w->scene, frame, &next, err);
  if (st == SATF_OK)
    st = satf_renderer_set_scene(w->r, next, NULL, err);
  satf_scene_destroy(w->snap);
  w->snap = next;
  return st;
}

void satf_frontend_walk_end(satf_frontend_walk *w, int ok) {
  if (w->snap) {
    satf_error ignore;
    satf_renderer_set_scene(w->r, w->scene, NULL, &ignore);
    satf_scene_destroy(w->snap);
    w->snap = NULL;
  }
  if (ok)
    *satf_renderer_camera(w->r) = w->start;
}

satf_status satf_frontend_bench(satf_renderer *r, const satf_scene *scene,
                                long frames, satf_frontend_present_fn present,
                                void *ctx, satf_frame_timing *mean, double *fps,
                                satf_error *err) {
  satf_frame_timing t;
  memset(mean, 0, sizeof *mean);
  satf_status st = satf_renderer_render(r, SATF_AOV_BEAUTY, &t, err);
  if (st == SATF_OK && present)
    st = present(ctx, err);
  if (st != SATF_OK)
    return st;
  satf_frontend_walk w;
  satf_frontend_walk_begin(&w, r, scene, frames);
  double b0 = satf_now_seconds(), n = (double)frames;
  for (long f = 0; f < frames && st == SATF_OK; f++) {
    double s0 = satf_now_seconds();
    st = satf_frontend_walk_step(&w, f, err);
    double s1 = satf_now_seconds();
    if (st == SATF_OK)
      st = satf_renderer_render(r, SATF_AOV_BEAUTY, &t, err);
    if (st == SATF_OK && present)
      st = present(ctx, err);
    if (st != SATF_OK)
      break;
    /* interpolating the frame and rebuilding moving clusters counts as
     * index calculation (Table 1's I) */
    t.index_ms += 1e3 * (s1 - s0);
    mean->index_ms += t.index_ms / n;
    mean->maps_ms += t.maps_ms / n;
    mean->upload_ms += t.upload_ms / n;
    mean->lighting_ms += t.lighting_ms / n;
    mean->shadow_ms += t.shadow_ms / n;
  }
  *fps = n / (satf_now_seconds() - b0);
  satf_frontend_walk_end(&w, st == SATF_OK);
  return st;
}
