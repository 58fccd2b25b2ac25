/* kdtree.c - see kdtree.h. Nodes are stored implicitly: the median of each
 * range is its node, split on the axis of largest spread. */
#include "kdtree.h"

#include <stdlib.h>
#include <string.h>

struct satf_kdtree {
  int n;
  float *pts;          /* reordered points, n x 3 */
  int *ids;            /* original index of each reordered point */
  unsigned char *axis; /* split axis of the node at each median slot */
};

static void swap_pt(satf_kdtree *t, int a, int b) {
  float tmp[3];
  memcpy(tmp, t->pts + 3 * a, sizeof tmp);
  memcpy(t->pts + 3 * a, t->pts + 3 * b, sizeof tmp);
  memcpy(t->pts + 3 * b, tmp, sizeof tmp);
  int id = t->ids[a];
  t->ids[a] = t->ids[b];
  t->ids[b] = id;
}

/* Less-than on (coordinate, original index), so equal coordinates still
 * order deterministically. */
static int less(const satf_kdtree *t, int a, int b, int ax) {
  float x = t->pts[3 * a + ax], y = t->pts[3 * b + ax];
  return x < y || (x == y && t->ids[a] < t->ids[b]);
}

/* Quickselect: puts the k-th element of [lo, hi) in place. */
static void select_kth(satf_kdtree *t, int lo, int hi, int k, int ax) {
  while (hi - lo > 1) {
    int mid = lo + (hi - lo) / 2;
    swap_pt(t, mid, hi - 1);
    int store = lo;
    for (int i = lo; i < hi - 1; i++)
      if (less(t, i, hi - 1, ax))
        swap_pt(t, i, store++);
    swap_pt(t, store, hi - 1);
    if (store == k)
      return;
    if (k < store)
      hi = store;
    else
      lo = store + 1;
  }
}

static void build(satf_kdtree *t, int lo, int hi) {
  if (hi - lo <= 0)
    return;
  float mn[3], mx[3];
  for (int a = 0; a < 3; a++)
    mn[a] = mx[a] = t->pts[3 * lo + a];
  for (int i = lo + 1; i < hi; i++)
    for (int a = 0; a < 3; a++) {
      float v = t->pts[3 * i + a];
      mn[a] = v < mn[a] ? v : mn[a];
      mx[a] = v > mx[a] ? v : mx[a];
    }
  int ax = 0;
  for (int a = 1; a < 3; a++)
    if (mx[a] - mn[a] > mx[ax] - mn[ax])
      ax = a;
  int mid = lo + (hi - lo) / 2;
  select_kth(t, lo, hi, mid, ax);
  t->axis[mid] = (unsigned char)ax;
  build(t, lo, mid);
  build(t, mid + 1, hi);
}

satf_kdtree *satf_kdtree_build(const float *points, int n) {
  satf_kdtree *t = calloc(1, sizeof *t);
  if (!t)
    return NULL;
  t->n = n;
  t->pts = malloc((size_t)(n > 0 ? n : 1) * 3 * sizeof(float));
  t->ids = malloc((size_t)(n > 0 ? n : 1) * sizeof(int));
  t->axis = malloc((size_t)(n > 0 ? n : 1));
  if (!t->pts || !t->ids || !t->axis) {
    satf_kdtree_destroy(t);
    return NULL;
  }
  if (n > 0)
    memcpy(t->pts, points, (size_t)n * 3 * sizeof(float));
  for (int i = 0; i < n; i++)
    t->ids[i] = i;
  build(t, 0, n);
  return t;
}

void satf_kdtree_destroy(satf_kdtree *t) {
  if (t) {
    free(t->pts);
    free(t->ids);
    free(t->axis);
    free(t);
  }
}

typedef struct knn {
  int k, found;
  int *index;
  float *dist2;
} knn;

/* Keeps the best k sorted by (distance, index). */
static void knn_offer(knn *h, int id, float d2) {
  if (h->found == h->k) {
    float worst = h->dist2[h->k - 1];
    if (d2 > worst || (d2 == worst && id > h->index[h->k - 1]))
      return;
    h->found--;
  }
  int i = h->found++;
  while (i > 0 && (h->dist2[i - 1] > d2 ||
                   (h->dist2[i - 1] == d2 && h->index[i - 1] > id))) {
    h->dist2[i] = h->dist2[i - 1];
    h->index[i] = h->index[i - 1];
    i--;
  }
  h->dist2[i] = d2;
  h->index[i] = id;
}

static void search(const satf_kdtree *t, int lo, int hi, const float q[3],
                   knn *h) {
  while (hi - lo > 0) {
    int mid = lo + (hi - lo) / 2;
    const float *p = t->pts + 3 * mid;
    float dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    knn_offer(h, t->ids[mid], dx * dx + dy * dy + dz * dz);
    int ax = t->axis[mid];
    float diff = q[ax] - p[ax];
    int near_lo = diff < 0 ? lo : mid + 1, near_hi = diff < 0 ? mid : hi;
    int far_lo = diff < 0 ? mid + 1 : lo, far_hi = diff < 0 ? hi : mid;
    search(t, near_lo, near_hi, q, h);
    if (h->found == h->k && diff * diff > h->dist2[h->k - 1])
      return;
    lo = far_lo;
    hi = far_hi;
  }
}

int satf_kdtree_nearest(const satf_kdtree *t, const float q[3], int k,
                        int *index, float *dist2) {
  if (k <= 0 || t->n == 0)
    return 0;
  if (k > t->n)
    k = t->n;
  knn h = {k, 0, index, dist2};
  search(t, 0, t->n, q, &h);
  return h.found;
}
