/* measure_tracks.c - how far the strands the renderer draws for clusters
 * rebuilt from their "tracks" (online/render/sparse.c, sparse_place) lie
 * from the scene's own strands (its "strands" file), and why. A measuring
 * program, not a test: `measure_tracks SCENE.json`.
 *
 * Every track of every cluster is placed as the renderer places it (the
 * cluster built as hierarchy.c builds it, the instance's transform) and
 * matched to the source strand whose root and tip lie nearest its ends.
 * Distances are taken both ways (rebuilt points to the source polyline and
 * source points to the rebuilt one), in scene units and in units of the
 * source strand's width (its mean thickness). The causes are separated by
 * rebuilding the source strand three ways on the same cluster:
 *   own t:  its points projected (satf_import_project_point) and put back
 *           at their own t (what the projection itself loses);
 *   slices: resampled at the scene's slices as satf-import does
 *           (satf_import_projection_at) and placed, ends included (adds
 *           the t resampling);
 *   scene:  the scene's tracks (adds the import's frame against the
 *           renderer's, and the JSON's rounding). */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "import_internal.h"
#include "mat4.h"
#include "measure_samples.h"
#include "renderer_internal.h"
#include "satf/geometry.h"
#include "satf/math.h"
#include "satf/scene.h"

static void report(const char *name, samples *s) {
  if (s->n == 0) {
    printf("  %-34s (none)\n", name);
    return;
  }
  samples_sort(s);
  double sum = 0.0;
  for (size_t i = 0; i < s->n; i++)
    sum += s->v[i];
  printf("  %-34s p50 %8.4f  p90 %8.4f  max %8.4f  mean %8.4f  (n %zu)\n", name,
         s->v[s->n / 2], s->v[(s->n * 9) / 10], s->v[s->n - 1],
         sum / (double)s->n, s->n);
  s->n = 0;
}

static float poly_dist(const float *p, const float *q, int n) {
  float best = FLT_MAX;
  for (int k = 0; k + 1 < n; k++)
    best = fminf(best, sqrtf(satf_segment_dist2f(p, q + 3 * k, q + 3 * k + 3)));
  return n == 1 ? sqrtf((p[0] - q[0]) * (p[0] - q[0]) +
                        (p[1] - q[1]) * (p[1] - q[1]) +
                        (p[2] - q[2]) * (p[2] - q[2]))
                : best;
}

static float dist3(const float *a, const float *b) {
  return sqrtf((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
               (a[2] - b[2]) * (a[2] - b[2]));
}

/* Both ways: rebuilt points to the source polyline into to_src, source
 * points to the rebuilt one into to_reb, each also over width w. */
static void both_ways(const float *reb, int nr, const float *src, int ns,
                      float w, samples *units, samples *widths) {
  for (int j = 0; j < nr; j++) {
    float d = poly_dist(reb + 3 * j, src, ns);
    push(units, d);
    push(widths, d / w);
  }
  for (int j = 0; j < ns; j++) {
    float d = poly_dist(src + 3 * j, reb, nr);
    push(units, d);
    push(widths, d / w);
  }
}

/* The source strand a rebuilt one stands for: of the CANDIDATES whose
 * root and tip lie nearest its two ends (either way round), the one its
 * points lie nearest on average (ends alone confuse strands that share a
 * root region or a tip region). */
enum { CANDIDATES = 24 };
static int match(const satf_strand_set *s, const float *reb, int nr) {
  int cand[CANDIDATES], nc = 0;
  float cd[CANDIDATES];
  const float *first = reb, *last = reb + 3 * (nr - 1);
  for (int i = 0; i < satf_strand_set_count(s); i++) {
    int n;
    const float *p = satf_strand_set_strand(s, i, &n);
    const float *q = p + 3 * (n - 1);
    float d = fminf(dist3(first, p) + dist3(last, q),
                    dist3(first, q) + dist3(last, p));
    if (nc < CANDIDATES || d < cd[nc - 1]) {
      int j = nc < CANDIDATES ? nc++ : nc - 1;
      for (; j > 0 && cd[j - 1] > d; j--) {
        cd[j] = cd[j - 1];
        cand[j] = cand[j - 1];
      }
      cd[j] = d;
      cand[j] = i;
    }
  }
  int best = -1;
  float bd = FLT_MAX;
  for (int c = 0; c < nc; c++) {
    int n;
    const float *p = satf_strand_set_strand(s, cand[c], &n);
    float sum = 0.0f;
    for (int j = 0; j < nr; j++)
      sum += poly_dist(reb + 3 * j, p, n);
    for (int j = 0; j < n; j++)
      sum += poly_dist(p + 3 * j, reb, nr);
    if (sum < bd) {
      bd = sum;
      best = cand[c];
    }
  }
  return best;
}

static float mean_width(const satf_strand_set *s, int i) {
  const float *th = satf_strand_set_thickness(s, i);
  int n = satf_strand_set_points(s, i);
  double sum = 0.0;
  for (int k = 0; th && k < n; k++)
    sum += th[k];
  return th ? (float)(sum / n) : 0.0f;
}

/* The section point at t, xy in the normalised cross-section, mapped by m
 * (the renderer's SATF eq. 1, as sparse.c with the cluster's own curves). */
static void place(const satf_cluster *cl, const float m[16], float t,
                  const float xy[2], float out[3]) {
  satf_cluster_section sec;
  satf_cluster_section_at(cl, t, &sec);
  float local[3];
  for (int c = 0; c < 3; c++)
    local[c] =
        sec.center[c] + sec.a * xy[0] * sec.n1[c] + sec.b * xy[1] * sec.n2[c];
  satf_mat4_point(m, local, out);
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: measure_tracks SCENE.json\n");
    return 2;
  }
  satf_scene *scene = NULL;
  satf_error err;
  if (satf_scene_load(argv[1], &scene, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return 1;
  }
  satf_strand_set *src = NULL;
  if (!scene->strands_file ||
      satf_hair_read(scene->strands_file, &src, &err) != SATF_OK) {
    fprintf(stderr, "no strands file: %s\n",
            scene->strands_file ? err.message : "(none)");
    return 1;
  }
  samples u = {0}, w = {0}, wr = {0}, own_u = {0}, own_w = {0}, sl_u = {0},
          sl_w = {0}, fr_w = {0}, single_w = {0}, single_u = {0};
  int clusters = 0, tracks = 0, instanced = 0;
  long own_bad[2] = {0, 0}, own_pts[2] = {0, 0};
  for (int m = 0; m < scene->n_macro_clusters; m++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[m];
    const satf_scene_cluster *c = &mc->prototype;
    const satf_scene_density *d = &c->density;
    if (d->type != SATF_SCENE_DENSITY_TRACKS)
      continue;
    /* the cluster as the renderer builds it */
    satf_cluster *cl = NULL;
    if (hierarchy_cluster_create(c, &cl, &err) != SATF_OK) {
      fprintf(stderr, "cluster %d: %s\n", m, err.message);
      return 1;
    }
    int multi = d->n_tracks >= 2;
    clusters += multi;
    instanced += mc->n_instances > 1 ? mc->n_instances - 1 : 0;
    int ns;
    size_t np;
    sparse_cluster_size(d, &ns, &np);
    int *counts = malloc(((size_t)ns + 1) * sizeof(int));
    float *xyz = malloc((3 * np + 3) * sizeof(float));
    float *width = malloc((np + 1) * sizeof(float));
    float denom = (float)(d->track_slices - 1);
    for (int i = 0; i < mc->n_instances; i++) {
      const float *mm = mc->instances[i].m;
      float inv[16];
      satf_mat4_invert(mm, inv);
      int got = sparse_place(cl, c, mm, counts, xyz, width);
      size_t at = 0;
      for (int k = 0; k < got; k++) {
        const float *reb = xyz + 3 * at;
        int nr = counts[k];
        int si = match(src, reb, nr);
        if (getenv("MEASURE_MATCH"))
          printf("match %d %d %d -> %d\n", m, i, k, si);
        int nsrc;
        const float *sp = satf_strand_set_strand(src, si, &nsrc);
        float sw = mean_width(src, si);
        if (!(sw > 0.0f))
          sw = 1.0f;
        samples *pu = multi ? &u : &single_u, *pw = multi ? &w : &single_w;
        both_ways(reb, nr, sp, nsrc, sw, pu, pw);
        if (multi) {
          tracks++;
          push(&wr, width[at] / sw);
          /* own t and slices, on the same cluster in its own space */
          satf_import_projection proj;
          size_t off[2] = {0, (size_t)nsrc};
          float *txy = malloc(3 * (size_t)nsrc * sizeof(float));
          float *own = malloc(3 * (size_t)nsrc * sizeof(float));
          for (int j = 0; j < nsrc; j++) {
            float local[3], dd;
            satf_mat4_point(inv, sp + 3 * j, local);
            satf_import_project_point(cl, local, txy + 3 * j, &dd,
                                      txy + 3 * j + 1);
            satf_cluster_section sec;
            satf_cluster_section_at(cl, txy[3 * j], &sec);
            txy[3 * j + 1] /= sec.a;
            txy[3 * j + 2] /= sec.b;
            place(cl, mm, txy[3 * j], txy + 3 * j + 1, own + 3 * j);
          }
          both_ways(own, nsrc, sp, nsrc, sw, &own_u, &own_w);
          for (int j = 0; j < nsrc; j++) {
            float dd = dist3(own + 3 * j, sp + 3 * j) / sw;
            int end = txy[3 * j] <= 0.0f || txy[3 * j] >= 1.0f;
            own_bad[end] += dd > 0.5f;
            own_pts[end]++;
          }
          proj.n_strands = 1;
          proj.offset = off;
          proj.txy = txy;
          float *sl = malloc(3 * ((size_t)d->track_slices + 2) * sizeof(float));
          int nsl = 0;
          float p[2];
          /* the lower-t end first, as satf-import writes ends */
          const float *e0 = txy, *e1 = txy + 3 * (nsrc - 1);
          if (e0[0] > e1[0]) {
            const float *sw2 = e0;
            e0 = e1;
            e1 = sw2;
          }
          place(cl, mm, e0[0], e0 + 1, sl);
          nsl = 1;
          for (int s = 0; s < d->track_slices; s++)
            if (satf_import_projection_at(&proj, 0, (float)s / denom, p))
              place(cl, mm, (float)s / denom, p, sl + 3 * nsl++);
          place(cl, mm, e1[0], e1 + 1, sl + 3 * nsl++);
          both_ways(sl, nsl, sp, nsrc, sw, &sl_u, &sl_w);
          /* the scene's rebuilt strand against the slices' one */
          float worst = 0.0f;
          for (int j = 0; j < nr; j++) {
            float dd = poly_dist(reb + 3 * j, sl, nsl) / sw;
            push(&fr_w, dd);
            worst = fmaxf(worst, dd);
          }
          if (getenv("MEASURE_VERBOSE") && worst > 1.0f)
            printf("cluster %d inst %d track %d: frame %.2f widths (%d "
                   "tracks, %d slices, %d ctrl, twist %.2f..%.2f)\n",
                   m, i, k, worst, d->n_tracks, d->track_slices, c->n_points,
                   c->twist.values[0], c->twist.values[c->twist.count - 1]);
          if (getenv("MEASURE_DUMP") && m == atoi(getenv("MEASURE_DUMP"))) {
            const float *tx = d->track_xy;
            for (int q = 0; q < k; q++)
              tx += 2 * d->track_count[q];
            printf(" track first %d count %d, src %d pts:\n", d->track_first[k],
                   d->track_count[k], nsrc);
            for (int j = 0; j < d->track_count[k]; j++)
              printf("  scene t %.3f xy %.3f %.3f\n",
                     (float)(d->track_first[k] + j) / denom, tx[2 * j],
                     tx[2 * j + 1]);
            for (int j = 0; j < nsrc; j++)
              printf("  src t %.3f xy %.3f %.3f\n", txy[3 * j], txy[3 * j + 1],
                     txy[3 * j + 2]);
          }
          free(sl);
          free(own);
          free(txy);
        }
        at += (size_t)nr;
      }
    }
    free(counts);
    free(xyz);
    free(width);
    satf_cluster_destroy(cl);
  }
  printf("%s: %d clusters of 2+ tracks, %d of their tracks; %d instances "
         "beyond their prototypes\n",
         argv[1], clusters, tracks, instanced);
  printf("clusters of 2+ strands, rebuilt vs source, both ways:\n");
  report("scene units", &u);
  report("strand widths", &w);
  report("drawn width / source width", &wr);
  printf("the same source strands rebuilt on the renderer's cluster "
         "(strand widths):\n");
  report("own t (projection only)", &own_w);
  printf("  own t off by > 0.5 widths: %ld of %ld points inside t (0, 1), "
         "%ld of %ld at t = 0 or 1 (beyond the trajectory's ends)\n",
         own_bad[0], own_pts[0], own_bad[1], own_pts[1]);
  report("slices + ends (t resampling)", &sl_w);
  report("scene vs slices (frame, rounding)", &fr_w);
  printf("  (own t in scene units, slices in scene units:)\n");
  report("own t, scene units", &own_u);
  report("slices, scene units", &sl_u);
  printf("one-track clusters, rebuilt vs source:\n");
  report("scene units", &single_u);
  report("strand widths", &single_w);
  satf_strand_set_destroy(src);
  satf_scene_destroy(scene);
  return 0;
}
