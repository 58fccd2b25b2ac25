/* frontend.c - see frontend.h. */
#include "frontend.h"

#include <string.h>

satf_status satf_frontend_load(const char *prog, const char *scene_path,
                               const char *db_path, long *width, long *height,
                               satf_frontend *fe) {
  memset(fe, 0, sizeof *fe);
  satf_error err;
  satf_error_clear(&err);
  satf_status st = satf_scene_load(scene_path, &fe->scene, &err);
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
  satf_db_destroy(fe->db);
  satf_scene_destroy(fe->scene);
  memset(fe, 0, sizeof *fe);
}

const char *const satf_frontend_effect_help =
    "  --no-satf            plain Kajiya-Kay with shifted highlights (paper "
    "002,\n"
    "                       Fig. 4a)\n"
    "  --no-secondary       no secondary highlight (Fig. 4b)\n"
    "  --no-self-shadow     no s-map self-shadowing (Fig. 4c)\n"
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
