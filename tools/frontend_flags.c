/* frontend_flags.c - the flags satf-render and satf-view share
 * (frontend.h): the effect switches of Fig. 4, the compositing, the
 * shading and the sparse clusters, with their help text. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "frontend.h"

const char *const satf_frontend_shading_help =
    "  --shading MODEL      kk: the paper's Kajiya-Kay lighting of the maps;\n"
    "                       physical: the fibre model (Cycles' Principled\n"
    "                       Hair) with a fibre database (satf-build --kind\n"
    "                       fiber; satf-fiber.hrirdb.exr beside the scene's\n"
    "                       Phong database is taken when there is no --db);\n"
    "                       default: the scene's material \"model\"\n";

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

const char *const satf_frontend_effect_help =
    "  --no-satf            Fig. 4a's baseline, Scheuermann 2004:\n"
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
