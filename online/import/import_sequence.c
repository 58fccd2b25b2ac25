/* import_sequence.c - a per-frame strand sequence as keyframes: every frame
 * is re-fitted onto the clusters of the first (the same member strands),
 * and each fit becomes a key of its macro-cluster's prototype (trajectory,
 * A, B and twist) in the scene being built. */
#define _POSIX_C_SOURCE 200809L
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>

#include "import_internal.h"
#include "satf/common.h"

static void frame_path(const char *pattern, long frame, char *out,
                       size_t size) {
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
  snprintf(out, size, pattern, (int)frame); /* one %d, checked by the caller */
#pragma GCC diagnostic pop
}

/* Frame fr's fits as keys of every macro-cluster's prototype. */
static satf_status add_frame(satf_scene *scene, const satf_import_options *o,
                             long fr, const int *labels, int n_strands,
                             const satf_import_fit_params *p,
                             const satf_import_macro *macro,
                             satf_import_fit *fits, satf_error *err) {
  char path[PATH_MAX];
  frame_path(o->inputs[0], fr, path, sizeof path);
  satf_strand_set *set = NULL;
  satf_status st = satf_import_read_strands(path, o, &set, err);
  if (st == SATF_OK && satf_strand_set_count(set) != n_strands)
    st = satf_error_set(err, SATF_ERR_FORMAT,
                        "%s: %d strands, but frame %ld had %d: a sequence "
                        "must keep its strands",
                        path, satf_strand_set_count(set), o->first, n_strands);
  if (st == SATF_OK) {
    satf_error fit_err;
    st = satf_import_fit_all(set, labels, macro->n_clusters, p, (int)o->threads,
                             fits, NULL, NULL, &fit_err);
    if (st != SATF_OK)
      satf_error_set(err, st, "%s: %s", path, fit_err.message);
  }
  for (int m = 0; st == SATF_OK && m < macro->n_macro; m++) {
    const satf_import_fit *fit = &fits[macro->prototype[m]];
    st = satf_scene_add_prototype_key(scene, m, (double)fr, fit->traj, fit->a,
                                      fit->b, fit->twist, err);
  }
  satf_strand_set_destroy(set);
  return st;
}

satf_status satf_import_sequence_keys(satf_scene *scene,
                                      const satf_import_options *o,
                                      const int *labels, int n_strands,
                                      const satf_import_fit_params *p,
                                      const satf_import_macro *macro,
                                      satf_error *err) {
  int n_clusters = macro->n_clusters;
  satf_status st = satf_scene_set_animation(scene, o->fps > 0 ? o->fps : 24.0,
                                            (int)o->first, (int)o->last, err);
  if (st != SATF_OK)
    return st;
  satf_import_fit *fits = calloc((size_t)n_clusters, sizeof *fits);
  if (!fits)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  satf_progress bar;
  satf_progress_begin(&bar, stderr, "frames", "frames", 1, o->quiet);
  for (long fr = o->first; fr <= o->last && st == SATF_OK; fr++) {
    st = add_frame(scene, o, fr, labels, n_strands, p, macro, fits, err);
    for (int c = 0; c < n_clusters; c++)
      satf_import_fit_free(&fits[c]);
    satf_progress_update(&bar, (size_t)(fr - o->first + 1),
                         (size_t)(o->last - o->first + 1));
  }
  satf_progress_end(&bar);
  free(fits);
  return st;
}
