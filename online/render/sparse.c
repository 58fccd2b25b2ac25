/* sparse.c - owns the clusters drawn as their own strands.
 * A cluster of a handful of strands fills no volume: SATF's shells
 * spread its strands' coverage over HSVs wider than the strands, so one
 * strand renders as a faint smear and a few as a twisted sheet. When a
 * prototype's density is "tracks" (the importer's record of where each
 * member strand crosses the cross-section, satf/scene.h) with at most
 * r->sparse_max strands, its instances are drawn instead as those
 * strands: each track, slice by slice, placed by the cluster's own
 * generalized cylinder (SATF eq. 1 with the twist, satf/geometry.h) and
 * the instance's transform, as anti-aliased ribbons (ribbons.c) of the
 * width the density assumes. In the exact mode they go into the same
 * per-pixel arrays as the clusters' fragments (strand_fs.glsl with LIST),
 * so the two are sorted together; in the ordered mode they are drawn at
 * their instance's place in the far-to-near order; they cast shadows into
 * the deep opacity map. Their clusters are neither looked up nor drawn. */
#include "renderer_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mat4.h"
#include "satf/math.h"

static float curve_mean(const satf_scene_curve *c) {
  double sum = 0.0;
  for (int i = 0; i < c->count; i++)
    sum += c->values[i];
  return c->count > 0 ? (float)(sum / c->count) : 0.0f;
}

static float curve_at(const satf_scene_curve *c, float t) {
  double v;
  satf_bspline_eval(c->values, c->count, 1, t, &v, NULL, NULL);
  return (float)v;
}

/* SATF eq. 1 at the normalised cross-section point xy = v (cos u, sin u):
 * T + A x e1 + B y e2, with the ellipse's axes e1, e2 the rotation-
 * minimising normals turned by theta (satf/geometry.h). A, B and theta
 * are the scene's own curves: the renderer's cluster takes them resampled
 * to the trajectory's control count (hierarchy.c), a slightly different
 * spline, and where a one-strand cluster's fitted twist swings by radians
 * between control points that difference moves the strand by its offset
 * from the trajectory; the importer placed the tracks with these. */
static void section_point(const satf_cluster *cluster,
                          const satf_scene_cluster *c, float t,
                          const float xy[2], float out[3]) {
  satf_cluster_section sec;
  satf_cluster_section_at(cluster, t, &sec);
  float a = curve_at(&c->a, t), b = curve_at(&c->b, t);
  float th = curve_at(&c->twist, t), ct = cosf(th), st = sinf(th);
  for (int k = 0; k < 3; k++) {
    float e1 = ct * sec.rmf_n1[k] + st * sec.rmf_n2[k];
    float e2 = -st * sec.rmf_n1[k] + ct * sec.rmf_n2[k];
    out[k] = sec.center[k] + a * xy[0] * e1 + b * xy[1] * e2;
  }
}

/* Track k's points: its slices, and its strand's root and tip where they
 * lie beyond them (the density's "ends"), whose (t, x, y) go into e. */
static int track_points(const satf_scene_density *d, int k, float e[6],
                        int *before, int *after) {
  float denom = d->track_slices > 1 ? (float)(d->track_slices - 1) : 1.0f;
  float t_lo = (float)d->track_first[k] / denom;
  float t_hi = (float)(d->track_first[k] + d->track_count[k] - 1) / denom;
  *before = *after = 0;
  if (d->track_ends) {
    memcpy(e, d->track_ends + 6 * (size_t)k, 6 * sizeof(float));
    float margin = SATF_SCENE_TRACK_END_MARGIN / denom;
    *before = e[0] < t_lo - margin;
    *after = e[3] > t_hi + margin;
  }
  return d->track_count[k] + *before + *after;
}

void sparse_cluster_size(const satf_scene_density *d, int *strands,
                         size_t *points) {
  *strands = 0;
  *points = 0;
  for (int k = 0; k < d->n_tracks; k++) {
    float e[6];
    int before, after, count = track_points(d, k, e, &before, &after);
    if (count >= 2) {
      (*strands)++;
      *points += (size_t)count;
    }
  }
}

/* Strands and points of every sparse instance. */
static void count_strands(const satf_renderer *r, int *strands,
                          size_t *points) {
  *strands = 0;
  *points = 0;
  for (int m = 0; m < r->nprotos; m++) {
    const proto *p = &r->protos[m];
    if (!p->sparse)
      continue;
    int n;
    size_t np;
    sparse_cluster_size(&r->scene->macro_clusters[m].prototype.density, &n,
                        &np);
    *strands += p->ninsts * n;
    *points += (size_t)p->ninsts * np;
  }
}

int sparse_place(const satf_cluster *cluster, const satf_scene_cluster *c,
                 const float m[16], int *counts, float *xyz, float *width) {
  const satf_scene_density *d = &c->density;
  /* "strand_width" (or each track's "widths") is a diameter in units of
   * the cluster radius sqrt(mean A * mean B) (satf/scene.h; what
   * satf-import writes and the strand reference draws), scaled by the
   * instance's size */
  float radius = sqrtf(curve_mean(&c->a) * curve_mean(&c->b));
  float unit = radius * cbrtf(fabsf(satf_mat4_det3(m)));
  float denom = d->track_slices > 1 ? (float)(d->track_slices - 1) : 1.0f;
  const float *xy = d->track_xy;
  int n = 0;
  size_t at = 0;
  for (int k = 0; k < d->n_tracks; k++) {
    float e[6];
    int before, after, count = track_points(d, k, e, &before, &after);
    if (count < 2) { /* a strand in one slice has no length to draw */
      xy += 2 * (size_t)d->track_count[k];
      continue;
    }
    float w = (d->track_width ? d->track_width[k] : d->strand_width) * unit;
    for (int j = 0; j < count; j++) {
      float t, local[3];
      const float *at_xy;
      if (j == 0 && before) {
        t = e[0];
        at_xy = e + 1;
      } else if (j == count - 1 && after) {
        t = e[3];
        at_xy = e + 4;
      } else {
        t = (float)(d->track_first[k] + j - before) / denom;
        at_xy = xy;
        xy += 2;
      }
      section_point(cluster, c, t, at_xy, local);
      satf_mat4_point(m, local, xyz + 3 * (at + (size_t)j));
      width[at + (size_t)j] = w;
    }
    counts[n++] = count;
    at += (size_t)count;
  }
  return n;
}

/* The strand's points (count, xyz and width) thinned in place to those a
 * polyline needs to stay within tol of all of them (Douglas-Peucker);
 * returns the points kept. A strand is drawn a quad a segment, and on
 * llvmpipe each of its small triangles costs: fur's tufts have about 7
 * points a strand through the slices and ends where a nearly straight
 * 4-point strand needs 2-4 (generated fur 20K, satf-render --bench 5,
 * interleaved under load: L 0.61-0.95x, images SSIM 0.997). */
static int thin_strand(float *xyz, float *width, int count, float tol) {
  enum { MAX = SATF_SCENE_MAX_TRACK_SLICES + 2 };
  if (count <= 2 || count > MAX || !(tol > 0.0f))
    return count;
  unsigned char keep[MAX] = {0};
  int stack[2 * MAX], top = 0;
  keep[0] = keep[count - 1] = 1;
  stack[top++] = 0;
  stack[top++] = count - 1;
  while (top > 0) {
    int b = stack[--top], a = stack[--top], far = -1;
    float worst = tol;
    for (int i = a + 1; i < b; i++) {
      float d =
          sqrtf(satf_segment_dist2f(xyz + 3 * i, xyz + 3 * a, xyz + 3 * b));
      if (d > worst) {
        worst = d;
        far = i;
      }
    }
    if (far < 0)
      continue;
    keep[far] = 1;
    stack[top++] = a;
    stack[top++] = far;
    stack[top++] = far;
    stack[top++] = b;
  }
  int n = 0;
  for (int i = 0; i < count; i++)
    if (keep[i]) {
      memmove(xyz + 3 * n, xyz + 3 * i, 3 * sizeof(float));
      width[n++] = width[i];
    }
  return n;
}

void sparse_release(satf_renderer *r) {
  strands_gpu_destroy(r->sparse);
  r->sparse = NULL;
  for (int m = 0; r->protos && m < r->nprotos; m++)
    r->protos[m].sparse = 0;
}

satf_status sparse_build(satf_renderer *r, satf_error *err) {
  sparse_release(r);
  for (int m = 0; m < r->nprotos; m++)
    r->protos[m].sparse =
        hierarchy_sparse(&r->scene->macro_clusters[m].prototype, r->sparse_max);
  int strands = 0;
  size_t points = 0;
  count_strands(r, &strands, &points);
  for (int i = 0; i < r->ninsts; i++)
    r->insts[i].seg0 = r->insts[i].nsegs = 0;
  if (strands == 0)
    return SATF_OK;
  int *counts = malloc((size_t)strands * sizeof(int));
  float *xyz = malloc(3 * points * sizeof(float));
  float *width = malloc(points * sizeof(float));
  satf_status st = SATF_OK;
  if (!counts || !xyz || !width)
    st = satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  int n = 0;
  size_t at = 0, seg = 0;
  for (int m = 0; m < r->nprotos && st == SATF_OK; m++) {
    const proto *p = &r->protos[m];
    for (int i = 0; p->sparse && i < p->ninsts; i++) {
      inst *in = &r->insts[p->first_inst + i];
      int got = sparse_place(p->cluster, &r->scene->macro_clusters[m].prototype,
                             in->m, counts + n, xyz + 3 * at, width + at);
      in->seg0 = seg;
      size_t from = at;
      for (int k = n; k < n + got; k++) {
        /* within a quarter of the strand's width: the drawn strand keeps
         * covering the line through its points; a tenth kept about 1.6
         * times the segments (docs/performance.md, "Strands among the
         * clusters": generated curls at 0.65-0.75x the frame rate, 0.002
         * closer to Cycles in SSIM4) */
        size_t c = (size_t)counts[k];
        if (from != at) {
          memmove(xyz + 3 * at, xyz + 3 * from, 3 * c * sizeof(float));
          memmove(width + at, width + from, c * sizeof(float));
        }
        from += c;
        counts[k] =
            thin_strand(xyz + 3 * at, width + at, counts[k], 0.25f * width[at]);
        at += (size_t)counts[k];
        seg += (size_t)counts[k] - 1;
      }
      in->nsegs = seg - in->seg0;
      n += got;
    }
  }
  if (st == SATF_OK)
    st = strands_gpu_create(n, counts, xyz, width, 0.0f, 1, 0, &r->sparse, err);
  if (st == SATF_OK && r->sparse)
    strands_gpu_in_order(r->sparse);
  r->sparse_sorted = 0;
  free(counts);
  free(xyz);
  free(width);
  if (st != SATF_OK)
    sparse_release(r);
  return st;
}

void sparse_lists(const satf_renderer *r, satf_aov aov,
                  const float viewproj[16], int mode) {
  if (!r->sparse)
    return;
  strands_gpu_begin(r, r->sparse, aov, viewproj, mode);
  strands_gpu_draw(r->sparse, 0, strands_gpu_segments(r->sparse));
}

int sparse_opaque_depth(const satf_renderer *r, const float viewproj[16]) {
  if (!r->sparse)
    return 0;
  glDisable(GL_CULL_FACE); /* a ribbon faces the eye either way round */
  return strands_gpu_opaque_depth(r, r->sparse, viewproj);
}

void sparse_dom(satf_renderer *r, int opacity) {
  if (r->sparse)
    strands_gpu_dom(r, r->sparse, opacity);
}

void sparse_ordered_begin(satf_renderer *r, satf_aov aov,
                          const float viewproj[16]) {
  if (r->sparse && r->sparse_sorted) { /* the instances' ranges again */
    strands_gpu_in_order(r->sparse);
    r->sparse_sorted = 0;
  }
  /* once a frame: binding the material, lights and view per instance cost
   * the ponytail's 584 sparse instances more than their draws */
  if (r->sparse)
    strands_gpu_begin(r, r->sparse, aov, viewproj, -1);
}

int sparse_only(const satf_renderer *r) {
  if (!r->sparse)
    return 0;
  for (int i = 0; i < r->ninsts; i++)
    if (!r->protos[r->insts[i].proto].sparse)
      return 0;
  return 1;
}

void sparse_composite(satf_renderer *r, satf_aov aov,
                      const float viewproj[16]) {
  strands_gpu_sort(r->sparse, r->view.camera.position);
  r->sparse_sorted = 1;
  strands_gpu_composite(r, r->sparse, aov, viewproj);
}

int sparse_ordered(satf_renderer *r, int i) {
  const inst *in = &r->insts[i];
  if (!r->protos[in->proto].sparse)
    return 0;
  if (r->sparse && in->nsegs > 0) {
    glDisable(GL_CULL_FACE); /* a ribbon faces the eye either way round */
    strands_gpu_use(r->sparse);
    strands_gpu_draw(r->sparse, in->seg0, in->nsegs);
  }
  return 1;
}
