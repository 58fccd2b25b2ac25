/* import_report.c - the honest fit report: how far the strands lie from
 * their cluster's trajectory and envelope surface, how much empty envelope
 * each strand brings, and which clusters are shorter than they are wide
 * (those render as rings), summarised over the clusters for satf-import's
 * summary and written per cluster for a closer look. An envelope inflated
 * until it holds the points hides every failure in "N% inside", so that
 * number is not reported. */
#define _POSIX_C_SOURCE 200809L
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "import_internal.h"
#include "satf/common.h"

static int cmp_float(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

/* p50, p90, max of v (sorted in place); with low, p50, p10 and min. */
static void over_clusters(float *v, int n, int low, float out[3]) {
  out[0] = out[1] = out[2] = 0.0f;
  if (n < 1)
    return;
  qsort(v, (size_t)n, sizeof(float), cmp_float);
  int p90 = (int)floor(0.9 * (n - 1) + 0.5),
      p10 = (int)floor(0.1 * (n - 1) + 0.5);
  out[0] = v[(n - 1) / 2];
  out[1] = low ? v[p10] : v[p90];
  out[2] = low ? v[0] : v[n - 1];
}

void satf_import_fit_stats_compute(const satf_import_fit *fits, int n,
                                   const satf_import_refine_params *rp,
                                   satf_import_fit_stats *out) {
  memset(out, 0, sizeof *out);
  out->clusters = n;
  out->tolerance = rp ? rp->tolerance : 0.0f;
  out->worst_trajectory = out->worst_aspect = -1;
  float *v = malloc((size_t)(n > 0 ? n : 1) * sizeof(float));
  if (!v || n < 1) {
    free(v);
    return;
  }
  float worst_t = -1.0f, worst_a = FLT_MAX;
  int shells = 0;
  for (int c = 0; c < n; c++) {
    const satf_import_fit_measures *m = &fits[c].measures;
    const satf_import_fit *f = &fits[c];
    int strands =
        satf_scene_tracks_as_strands(f->track_slices, f->n_tracks,
                                     f->track_count, SATF_SCENE_SPARSE_STRANDS);
    out->as_strands += strands;
    out->strands += f->strands;
    out->shell_strands += strands ? 0 : f->strands;
    out->tufts += strands && f->strands > SATF_SCENE_SPARSE_STRANDS;
    /* the direction over the clusters drawn as shells (those drawn as
     * their strands are shaded along each strand), gathered into v first */
    if (!strands) {
      v[shells++] = m->direction[1];
      if (m->direction[1] > SATF_IMPORT_ACROSS_DEGREES)
        out->across_strands += f->strands;
    }
    /* a cluster drawn as its strands is no ring however short */
    out->rings += m->aspect < 1.0f && !strands;
    out->single += fits[c].strands == 1;
    if (rp)
      out->over += satf_import_fit_score(&fits[c], rp) > 1.0f;
    if (m->trajectory[1] > worst_t) {
      worst_t = m->trajectory[1];
      out->worst_trajectory = c;
    }
    if (m->aspect < worst_a) {
      worst_a = m->aspect;
      out->worst_aspect = c;
    }
  }
  over_clusters(v, shells, 0, out->direction);
  for (int c = 0; c < n; c++)
    v[c] = fits[c].measures.trajectory[1];
  over_clusters(v, n, 0, out->trajectory);
  for (int c = 0; c < n; c++)
    v[c] = fits[c].measures.surface[1];
  over_clusters(v, n, 0, out->surface);
  for (int c = 0; c < n; c++)
    v[c] = fits[c].measures.outside[1];
  over_clusters(v, n, 0, out->outside);
  for (int c = 0; c < n; c++)
    v[c] = fits[c].measures.area_per_strand;
  over_clusters(v, n, 0, out->area_per_strand);
  for (int c = 0; c < n; c++)
    v[c] = fits[c].measures.aspect;
  over_clusters(v, n, 1, out->aspect);
  free(v);
}

void satf_import_fit_stats_print(FILE *out, const char *prog,
                                 const satf_import_fit_stats *st) {
  const float *t = st->trajectory, *s = st->surface, *o = st->outside;
  const float *a = st->area_per_strand, *q = st->aspect;
  fprintf(out,
          "  fit (per cluster p90 of its points; p50 / p90 / max over "
          "clusters)\n"
          "    to trajectory  %.4g / %.4g / %.4g (worst: cluster %d)\n"
          "    to envelope    %.4g / %.4g / %.4g; outside it by %.4g / %.4g "
          "/ %.4g\n"
          "    area/strand    %.4g / %.4g / %.4g (envelope area per member "
          "strand)\n"
          "    length/diam.   p50 %.3g, p10 %.3g, min %.3g (cluster %d)\n",
          (double)t[0], (double)t[1], (double)t[2], st->worst_trajectory,
          (double)s[0], (double)s[1], (double)s[2], (double)o[0], (double)o[1],
          (double)o[2], (double)a[0], (double)a[1], (double)a[2], (double)q[0],
          (double)q[1], (double)q[2], st->worst_aspect);
  if (st->shell_strands > 0)
    fprintf(out,
            "    direction      %.3g / %.3g / %.3g degrees to the trajectory "
            "(shell clusters); %lld%% of shell strands where over %g\n",
            (double)st->direction[0], (double)st->direction[1],
            (double)st->direction[2],
            100 * st->across_strands / st->shell_strands,
            (double)SATF_IMPORT_ACROSS_DEGREES);
  if (st->tolerance > 0.0f)
    fprintf(out,
            "    tolerance      %.4g: %d of %d clusters over it (%d of one "
            "strand)\n",
            (double)st->tolerance, st->over, st->clusters, st->single);
  fprintf(out,
          "    as strands     %d of %d clusters are drawn as their strands "
          "(%d tufts of short strands), %d as shells\n",
          st->as_strands, st->clusters, st->tufts,
          st->clusters - st->as_strands);
  /* the share SATF's shells draw: the method's own, against what falls
   * back to the strand path */
  fprintf(out, "  shells           %lld%% of %lld strands in %d clusters\n",
          st->strands > 0 ? 100 * st->shell_strands / st->strands : 0,
          st->strands, st->clusters - st->as_strands);
  if (st->rings > 0)
    fprintf(out,
            "%s: warning: %d of %d clusters are shorter than their diameter "
            "and will render as rings (try without --clusters, or a higher "
            "--quality)\n",
            prog, st->rings, st->clusters);
}

satf_status satf_import_write_fit_report(const char *path,
                                         const satf_import_fit *fits, int n,
                                         satf_error *err) {
  size_t cap = 512 + (size_t)n * 336, len = 0;
  char *buf = malloc(cap);
  if (!buf)
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  len += (size_t)snprintf(
      buf + len, cap - len,
      "cluster\tstrands\tpoints\tcontrol\tlength\tdiameter\taspect\t"
      "area_per_strand\ttraj_p50\ttraj_p90\ttraj_max\tsurf_p50\tsurf_p90\t"
      "surf_max\tout_p50\tout_p90\tout_max\tdir_p50\tdir_p90\tdir_max\tcurl\n");
  for (int c = 0; c < n && len < cap; c++) {
    const satf_import_fit *f = &fits[c];
    const satf_import_fit_measures *m = &f->measures;
    len += (size_t)snprintf(
        buf + len, cap - len,
        "%d\t%d\t%zu\t%d\t%.6g\t%.6g\t%.4g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t"
        "%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.4g\t%.4g\t%.4g\t%.4g\n",
        c, f->strands, f->points, f->n_ctrl, (double)f->length,
        (double)m->diameter, (double)m->aspect, (double)m->area_per_strand,
        (double)m->trajectory[0], (double)m->trajectory[1],
        (double)m->trajectory[2], (double)m->surface[0], (double)m->surface[1],
        (double)m->surface[2], (double)m->outside[0], (double)m->outside[1],
        (double)m->outside[2], (double)m->direction[0], (double)m->direction[1],
        (double)m->direction[2], (double)f->curl);
  }
  satf_status st = SATF_OK;
  if (len >= cap)
    st = satf_error_set(err, SATF_ERR_INTERNAL, "%s: report overflow", path);
  else
    st = satf_write_file_atomic(path, buf, len, err);
  free(buf);
  return st;
}
