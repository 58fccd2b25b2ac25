/* directions.c - see satf_sector_hair_directions in density.h. */
#include "satf/density.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "satf/math.h"

typedef struct directions_job {
  const satf_cluster *cluster;
  const satf_shell_params *shell;
  const satf_scene_density *d;
  const size_t *offset;             /* track k's first (x, y) pair */
  const satf_cluster_section *secs; /* one per track slice */
  float *sums;                      /* (st + 1) x su x 3, unnormalised */
} directions_job;

/* Point (x, y) = v (cos u, sin u) of the normalised cross-section of
 * section sec: SATF eq. 1, C + A x n1 + B y n2 on the turned axes. */
static void section_xy(const satf_cluster_section *sec, const float xy[2],
                       float p[3]) {
  for (int c = 0; c < 3; c++)
    p[c] = sec->center[c] + sec->a * xy[0] * sec->n1[c] +
           sec->b * xy[1] * sec->n2[c];
}

/* Boundary i: every track present over the slice interval that holds t_i
 * adds its chord's unit direction to the phase column its point at t_i
 * lies in. */
static int directions_boundary(void *vctx, size_t i, int thread) {
  (void)thread;
  const directions_job *job = vctx;
  const satf_shell_params *sh = job->shell;
  const satf_scene_density *d = job->d;
  float g = (float)i / (float)sh->st * (float)(d->track_slices - 1);
  int s = (int)floorf(g);
  if (s > d->track_slices - 2)
    s = d->track_slices - 2;
  float f = g - (float)s;
  float *row = job->sums + i * (size_t)sh->su * 3;
  for (int k = 0; k < d->n_tracks; k++) {
    int first = d->track_first[k], last = first + d->track_count[k] - 1;
    if (s < first || s + 1 > last)
      continue;
    const float *a = d->track_xy + 2 * (job->offset[k] + (size_t)(s - first));
    const float *b = a + 2;
    float p0[3], p1[3], c[3];
    section_xy(&job->secs[s], a, p0);
    section_xy(&job->secs[s + 1], b, p1);
    for (int q = 0; q < 3; q++)
      c[q] = p1[q] - p0[q];
    float len = sqrtf(satf_dot3f(c, c));
    if (!(len > 0.0f))
      continue;
    float x = a[0] + f * (b[0] - a[0]), y = a[1] + f * (b[1] - a[1]);
    float u = atan2f(y, x);
    if (u < 0.0f)
      u += SATF_TWO_PI_F;
    int j = (int)(u / SATF_TWO_PI_F * (float)sh->su);
    j = j < 0 ? 0 : j >= sh->su ? sh->su - 1 : j;
    for (int q = 0; q < 3; q++)
      row[3 * j + q] += c[q] / len;
  }
  return 0;
}

satf_status satf_sector_hair_directions(const satf_cluster *cluster,
                                        const satf_shell_params *shell,
                                        const satf_scene_density *density,
                                        int threads, float *dirs,
                                        satf_error *err) {
  if (density->type != SATF_SCENE_DENSITY_TRACKS)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "hair directions need the strands' tracks");
  satf_status st = satf_shell_params_check(shell, err);
  if (st != SATF_OK)
    return st;
  if (density->track_slices < 2 || density->n_tracks < 0)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "tracks density: %d tracks over %d slices",
                          density->n_tracks, density->track_slices);
  size_t n = ((size_t)shell->st + 1) * (size_t)shell->su * 3;
  float *sums = calloc(n, sizeof *sums);
  size_t *offset = malloc(((size_t)density->n_tracks + 1) * sizeof *offset);
  satf_cluster_section *secs =
      malloc((size_t)density->track_slices * sizeof *secs);
  if (!sums || !offset || !secs) {
    free(sums);
    free(offset);
    free(secs);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot allocate the hair directions of %zu sectors",
                          n / 3);
  }
  size_t at = 0;
  for (int k = 0; k < density->n_tracks; k++) {
    offset[k] = at;
    at += (size_t)density->track_count[k];
  }
  for (int s = 0; s < density->track_slices; s++)
    satf_cluster_section_at(
        cluster, (float)s / (float)(density->track_slices - 1), &secs[s]);
  directions_job job = {cluster, shell, density, offset, secs, sums};
  int failed = satf_parallel_for((size_t)shell->st + 1, threads,
                                 directions_boundary, &job, NULL, NULL);
  free(offset);
  free(secs);
  if (failed) {
    free(sums);
    return satf_error_set(err, SATF_ERR_INTERNAL,
                          "hair direction computation failed");
  }
  /* each phase column with the two beside it, in every layer: a sector
   * holds a few strands, whose chords scatter about the wisp's course
   * (docs/shading.md, "Where the strands run") */
  int su = shell->su;
  for (int i = 0; i <= shell->st; i++) {
    const float *row = sums + (size_t)i * su * 3;
    for (int j = 0; j < su; j++) {
      float m[3] = {0.0f, 0.0f, 0.0f};
      for (int dj = -1; dj <= 1; dj++) {
        const float *c = row + 3 * ((j + dj + su) % su);
        for (int q = 0; q < 3; q++)
          m[q] += c[q];
      }
      float len = sqrtf(satf_dot3f(m, m));
      for (int k = 0; k < shell->layers; k++) {
        float *o = dirs + 3 * (((size_t)i * shell->layers + k) * su + j);
        for (int q = 0; q < 3; q++)
          o[q] = len > 1e-6f ? m[q] / len : 0.0f;
      }
    }
  }
  free(sums);
  return SATF_OK;
}
