/* lod.c - owns the clusters' level of detail: which
 * shell layers the shading pass reads and which proxy is drawn, per
 * cluster per frame from its size on screen (the rules: lod_frame.c
 * applies them each frame).
 *
 * Layers. A cluster a few pixels wide cannot show its shells apart, yet
 * each of its fragments traces every shell (glsl/shade_fs.glsl). At level
 * n it reads every 2^n-th shell from the outermost, and each read shell
 * stands for the 2^n inwards of it: its alpha a becomes 1 - (1 - a)^m
 * for the m shells it covers (SATF eq. 14 over equal layers; a mean alpha
 * of the skipped shells, read from a buffer per layer, fitted sparse
 * clusters better but cost more than the layers it saved on llvmpipe).
 * Between levels n and n + 1 the shells level n + 1 drops keep a weight
 * 1 - f and those it keeps take f of them, so the image is continuous in
 * the level and the level continuous in the width on screen (log2 full_px
 * / width): no popping, and no second evaluation in the band (it costs
 * what level n costs). Our choice, measured against full detail in
 * docs/performance.md ("Level of detail"): the paper has no level of
 * detail.
 *
 * Proxies. Shading traces the shells analytically, so the proxy only has
 * to cover the silhouette; a CPU rasteriser pays for each triangle, so a
 * thin cluster takes a ring of 6 columns instead of 12, on every second
 * HSV row where the two-row bands depart from the shell by under sag_px.
 * The proxy sets each fragment's depth, by which exact compositing sorts
 * interleaved clusters and the meshes' depth test culls, so it is kept to
 * clusters a few pixels wide. It is discrete, so it changes only when the
 * size leaves its threshold by the hysteresis: a cluster at a threshold
 * does not switch every frame. */
#include "lod.h"

#include <math.h>
#include <string.h>

#include "satf/math.h"

int lod_proxy_rows(int p) {
  return p == LOD_PROXY_THIN_HALF_ROWS ? 2 : p == LOD_PROXY_DOM ? 4 : 1;
}

int lod_proxy_thin(int p) {
  return p == LOD_PROXY_THIN || p == LOD_PROXY_THIN_HALF_ROWS;
}

lod_params lod_defaults(void) {
  lod_params p = {24.0f, 8.0f, 0.1f, 0.15f};
  return p;
}

int lod_level_cap(int layers) {
  int cap = 0;
  while ((1 << cap) < layers)
    cap++;
  return cap;
}

float lod_level(float width_px, int layers, const lod_params *p) {
  if (!(width_px < p->full_px) || layers <= 1)
    return 0.0f;
  float cap = (float)lod_level_cap(layers);
  float level = width_px > 0.0f ? log2f(p->full_px / width_px) : cap;
  return level < cap ? level : cap;
}

float lod_layer_share(float level, int k, int layers) {
  if (!(level > 0.0f))
    return 1.0f;
  int n = (int)level;
  float f = level - (float)n;
  int m1 = 1 << n, m2 = m1 << 1;
  int j = layers - 1 - k; /* 0: the outermost */
  int left = layers - j;  /* shells from this one inwards */
  int own = m1 < left ? m1 : left;
  if (j % m2 == 0) { /* kept at both levels: takes the dropped one's share */
    int more = left - m1 < 0 ? 0 : left - m1 < m1 ? left - m1 : m1;
    return (float)own + f * (float)more;
  }
  if (j % m2 == m1) /* dropped at level n + 1 */
    return (1.0f - f) * (float)own;
  return 0.0f;
}

/* The coarsest proxy for sizes multiplied by `scale`. */
static int coarsest(float width_px, float sag_px, float scale,
                    const lod_params *p) {
  if (width_px * scale > p->thin_px)
    return LOD_PROXY_FULL;
  return sag_px * scale <= p->sag_px ? LOD_PROXY_THIN_HALF_ROWS
                                     : LOD_PROXY_THIN;
}

int lod_proxy(float width_px, float sag_px, int current, const lod_params *p) {
  if (current < 0 || current > LOD_PROXY_THIN_HALF_ROWS)
    return coarsest(width_px, sag_px, 1.0f, p);
  /* the proxies are ordered fine to coarse; sizes a little larger give
   * the finest acceptable now, a little smaller the coarsest */
  int fine = coarsest(width_px, sag_px, 1.0f + p->hysteresis, p);
  int coarse = coarsest(width_px, sag_px, 1.0f - p->hysteresis, p);
  return current < fine ? fine : current > coarse ? coarse : current;
}

/* |a - b| of two 3-vectors. */
static float distance3(const float *a, const float *b) {
  float d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  return sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

void lod_measure(const float *v, size_t n, int stride, int cols, int st,
                 float sphere[4], float *width, float *sag) {
  memset(sphere, 0, 4 * sizeof(float));
  *width = *sag = 0.0f;
  if (n == 0)
    return;
  for (size_t i = 0; i < n; i++)
    for (int a = 0; a < 3; a++)
      sphere[a] += v[(size_t)stride * i + (size_t)a] / (float)n;
  for (size_t i = 0; i < n; i++) {
    const float *q = v + (size_t)stride * i;
    float r = distance3(q, sphere);
    float w = 2.0f * (q[17] > q[18] ? q[17] : q[18]);
    sphere[3] = r > sphere[3] ? r : sphere[3];
    *width = w > *width ? w : *width;
  }
  /* the bands of two rows: rows i, i + 2 (the last one ends at st) */
  size_t row = (size_t)stride * (size_t)cols;
  for (int i = 0; i + 1 < st; i += 2) {
    const float *a = v + row * (size_t)i, *m = a + row, *b = m + row;
    float mid[3], axis[3], len = 0.0f;
    for (int k = 0; k < 3; k++) {
      mid[k] = 0.5f * (a[8 + k] + b[8 + k]);
      axis[k] = a[11 + k] + b[11 + k];
      len += axis[k] * axis[k];
    }
    len = len > 0.0f ? sqrtf(len) : 1.0f;
    for (int k = 0; k < 3; k++)
      axis[k] /= len;
    float radius = m[17] > m[18] ? m[17] : m[18];
    float d = distance3(m + 8, mid) + radius * distance3(m + 11, axis);
    *sag = d > *sag ? d : *sag;
  }
}
