/* frontend_strands.c - --strands (frontend.h): the scene's source strands
 * drawn instead of its clusters, at their own, a given or the density's
 * width. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "frontend.h"

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
  float assumed = have ? 0.0f : satf_scene_density_strand_width(fe->scene);
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

const char *const satf_frontend_strand_help =
    "  --strands            draw the scene's source strands (its \"strands\"\n"
    "                       .hair file) instead of the clusters: the\n"
    "                       reference the clusters approximate, same lights,\n"
    "                       material, shading and shadows (slow)\n"
    "  --strand-width W     with --strands: every strand W scene units wide\n"
    "                       (default: the file's thickness); 'density': the\n"
    "                       width the clusters' density assumes (median of\n"
    "                       strand_width x cluster radius)\n";
