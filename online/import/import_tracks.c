/* import_tracks.c - a cluster's density from its own strands
 * (scene density type "tracks", online/density/tracks.c): where
 * each member strand crosses evenly spaced t slices of the fitted cluster,
 * in its normalised cross-section, from the first slice it reaches to the
 * last. The renderer's sector features (SATF sec. 5.2) then see the file's
 * strands where they really are, and a cluster thins out where its strands
 * end instead of stopping at t = 1. */
#include <math.h>
#include <stdlib.h>

#include "import_internal.h"

/* Slices per cluster: two per HSV along t (the shell's st, about one per
 * cluster width), so a strand that winds about the axis is followed
 * between the sectors' own t; and for a cluster of few strands, which the
 * renderer draws as those strands rebuilt from their tracks
 * (SATF_SCENE_SPARSE_STRANDS), at least as many as its longest strand has
 * points, so a curl is not cut short into a polygon of a few slices. */
static int slice_count(const satf_import_projection *proj,
                       const satf_import_fit *fit) {
  satf_scene_shell sh = satf_import_choose_shell(fit);
  int n = 2 * sh.st + 1;
  if (proj->n_strands <= SATF_SCENE_SPARSE_STRANDS)
    for (int i = 0; i < proj->n_strands; i++) {
      size_t points = proj->offset[i + 1] - proj->offset[i];
      n = points > (size_t)n ? (int)(points < 1000 ? points : 1000) : n;
    }
  return n < 9 ? 9 : n > 129 ? 129 : n;
}

/* Rounded to 1e-4 of the cluster radius: the scene stays small, and a
 * strand's place is known to far better than its width. */
static float round4(float v) { return roundf(v * 1e4f) * 1e-4f; }

static float clamp_coord(float v) {
  /* the scene format holds |x|, |y| <= 8: strands beyond 8 radii are far
   * outside the shells the features sample */
  return round4(fminf(fmaxf(v, -8.0f), 8.0f));
}

/* Strand i's root and tip in the cluster's coordinates, the lower t
 * first, into e[6]. A strand starts and stops between slices: its track
 * alone draws it short by up to a slice interval at each end (fur: a
 * quarter of a 4-slice strand). Returns whether either end lies beyond
 * the track's slices t_lo .. t_hi. */
static int track_ends(const satf_import_projection *proj, int i, float t_lo,
                      float t_hi, float step, float e[6]) {
  const float *q = proj->txy + 3 * proj->offset[i];
  const float *r = proj->txy + 3 * (proj->offset[i + 1] - 1);
  if (q[0] > r[0]) {
    const float *swap = q;
    q = r;
    r = swap;
  }
  const float *end[2] = {q, r};
  for (int k = 0; k < 2; k++) {
    e[3 * k] = round4(fminf(fmaxf(end[k][0], 0.0f), 1.0f));
    e[3 * k + 1] = clamp_coord(end[k][1]);
    e[3 * k + 2] = clamp_coord(end[k][2]);
  }
  float margin = SATF_SCENE_TRACK_END_MARGIN * step;
  return e[0] < t_lo - margin || e[3] > t_hi + margin;
}

void satf_import_fit_tracks(const satf_import_projection *proj,
                            satf_import_fit *fit) {
  free(fit->track_first);
  free(fit->track_count);
  free(fit->track_xy);
  free(fit->track_ends);
  free(fit->track_member);
  free(fit->track_width);
  fit->track_first = fit->track_count = fit->track_member = NULL;
  fit->track_xy = fit->track_ends = fit->track_width = NULL;
  fit->n_tracks = 0;
  int n = proj->n_strands, slices = slice_count(proj, fit);
  int *first = malloc(((size_t)n + 1) * sizeof(int));
  int *count = malloc(((size_t)n + 1) * sizeof(int));
  float *xy = malloc(((size_t)n * (size_t)slices * 2 + 1) * sizeof(float));
  float *ends = malloc((6 * (size_t)n + 1) * sizeof(float));
  int *member = malloc(((size_t)n + 1) * sizeof(int));
  if (!first || !count || !xy || !ends || !member) {
    /* procedural density stands in */
    free(first);
    free(count);
    free(xy);
    free(ends);
    free(member);
    return;
  }
  size_t at = 0;
  int kept = 0, beyond = 0;
  for (int i = 0; i < n; i++) {
    int lo = -1, hi = -1;
    float p[2];
    for (int s = 0; s < slices; s++)
      if (satf_import_projection_at(proj, i, (float)s / (float)(slices - 1),
                                    p)) {
        if (lo < 0)
          lo = s;
        hi = s;
      }
    if (lo < 0) /* shorter than a slice interval: no slice sees it */
      continue;
    first[kept] = lo;
    member[kept] = i;
    count[kept] = hi - lo + 1;
    float last[2] = {0.0f, 0.0f};
    for (int s = lo; s <= hi; s++) {
      /* a strand doubling back may skip a slice: hold its last place */
      if (satf_import_projection_at(proj, i, (float)s / (float)(slices - 1),
                                    p)) {
        last[0] = p[0];
        last[1] = p[1];
      }
      xy[2 * at] = clamp_coord(last[0]);
      xy[2 * at + 1] = clamp_coord(last[1]);
      at++;
    }
    float step = 1.0f / (float)(slices - 1);
    beyond |= track_ends(proj, i, (float)lo * step, (float)hi * step, step,
                         ends + 6 * kept);
    kept++;
  }
  fit->track_slices = slices;
  fit->n_tracks = kept;
  fit->track_first = first;
  fit->track_count = count;
  fit->track_xy = xy;
  fit->track_member = member;
  if (beyond) /* else the slices hold every strand end to end */
    fit->track_ends = ends;
  else
    free(ends);
}
