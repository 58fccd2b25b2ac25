/* Owns the width of strands whose file gives none (TressFX, strand PLY,
 * USC .data): measured once from the hairstyle's own spacing, before any
 * clustering, so that the strand file written beside the scene, the
 * strand reference (satf-render --strands), lone strands' clusters and the
 * shells' density all assume the same strands whatever the clustering or
 * --quality (a width measured inside each cluster made the reference
 * itself change with the clustering: the ponytail's references at the
 * default and the high quality scored SSIM 0.41 against each other). */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "import_internal.h"
#include "satf/common.h"
#include "satf/math.h"

/* Cells of the segment grid: a cell is a segment's median length, so a
 * segment touches a few cells and a point's 27 neighbouring cells hold
 * every segment nearer than one cell. */
typedef struct {
  uint64_t key;
  int segment;
} cell_entry;

typedef struct {
  const satf_strand_set *s;
  const int *owner; /* strand of each segment */
  const float *a;   /* segment start, 3 floats */
  const float *b;   /* segment end */
  const cell_entry *cells;
  size_t n_cells;
  float lo[3], cell;
  float *spacing;  /* per strand: median distance to another strand */
  float **scratch; /* per thread, room for the longest strand */
} grid;

#define AXIS_BITS 21
#define AXIS_MAX ((1 << AXIS_BITS) - 1)

static uint64_t cell_key(int x, int y, int z) {
  return ((uint64_t)x << (2 * AXIS_BITS)) | ((uint64_t)y << AXIS_BITS) |
         (uint64_t)z;
}

static int cell_of(const grid *g, float v, int c) {
  float f = floorf((v - g->lo[c]) / g->cell);
  return f < 0.0f ? 0 : f > (float)AXIS_MAX ? AXIS_MAX : (int)f;
}

static int cmp_entry(const void *x, const void *y) {
  const cell_entry *p = x, *q = y;
  if (p->key != q->key)
    return p->key < q->key ? -1 : 1;
  return (p->segment > q->segment) - (p->segment < q->segment);
}

static int cmp_float(const void *x, const void *y) {
  float p = *(const float *)x, q = *(const float *)y;
  return (p > q) - (p < q);
}

static float median_of(float *v, int n) {
  qsort(v, (size_t)n, sizeof *v, cmp_float);
  return v[n / 2];
}

/* The first entry of a cell (or n_cells). */
static size_t find_cell(const grid *g, uint64_t key) {
  size_t lo = 0, hi = g->n_cells;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (g->cells[mid].key < key)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

/* Distance from p to the nearest segment of another strand among the 27
 * cells around p; FLT_MAX if none is there. */
static float nearest_other(const grid *g, const float p[3], int strand) {
  int c0[3];
  for (int c = 0; c < 3; c++)
    c0[c] = cell_of(g, p[c], c);
  float best = FLT_MAX;
  for (int dx = -1; dx <= 1; dx++)
    for (int dy = -1; dy <= 1; dy++)
      for (int dz = -1; dz <= 1; dz++) {
        int x = c0[0] + dx, y = c0[1] + dy, z = c0[2] + dz;
        if (x < 0 || y < 0 || z < 0 || x > AXIS_MAX || y > AXIS_MAX ||
            z > AXIS_MAX)
          continue;
        uint64_t key = cell_key(x, y, z);
        for (size_t i = find_cell(g, key);
             i < g->n_cells && g->cells[i].key == key; i++) {
          int sg = g->cells[i].segment;
          if (g->owner[sg] == strand)
            continue;
          float d2 = satf_segment_dist2f(p, g->a + 3 * (size_t)sg,
                                         g->b + 3 * (size_t)sg);
          if (d2 < best)
            best = d2;
        }
      }
  return best < FLT_MAX ? sqrtf(best) : FLT_MAX;
}

/* One strand's spacing: the median over its points (the root and tip
 * left out where there are more than two: roots crowd on a scalp, tips
 * gather) of the distance to the nearest other strand; FLT_MAX where no
 * other strand is within a cell. */
static int strand_spacing(void *ctx, size_t i, int thread) {
  grid *g = ctx;
  int m;
  const float *p = satf_strand_set_strand(g->s, (int)i, &m);
  int k0 = m > 2 ? 1 : 0, k1 = m > 2 ? m - 1 : m;
  float *d = g->scratch[thread];
  int n = 0;
  for (int k = k0; k < k1; k++) {
    float r = nearest_other(g, p + 3 * k, (int)i);
    if (r < FLT_MAX)
      d[n++] = r;
  }
  g->spacing[i] = n > 0 ? median_of(d, n) : FLT_MAX;
  return 0;
}

static satf_status build_grid(grid *g, int n_segments, satf_error *err) {
  /* a segment's cells: its bounding box's, at most 4 per axis (longer
   * segments are rare: the cell is the median length) */
  size_t cap = (size_t)n_segments * 8, n = 0;
  cell_entry *e = malloc(cap * sizeof *e);
  if (!e)
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "strand spacing: out of memory for %d segments",
                          n_segments);
  for (int sg = 0; sg < n_segments; sg++) {
    const float *a = g->a + 3 * (size_t)sg, *b = g->b + 3 * (size_t)sg;
    int lo[3], hi[3];
    for (int c = 0; c < 3; c++) {
      lo[c] = cell_of(g, fminf(a[c], b[c]), c);
      hi[c] = cell_of(g, fmaxf(a[c], b[c]), c);
      if (hi[c] - lo[c] > 3)
        hi[c] = lo[c] + 3;
    }
    for (int x = lo[0]; x <= hi[0]; x++)
      for (int y = lo[1]; y <= hi[1]; y++)
        for (int z = lo[2]; z <= hi[2]; z++) {
          if (n == cap) {
            cell_entry *grown = realloc(e, 2 * cap * sizeof *e);
            if (!grown) {
              free(e);
              return satf_error_set(err, SATF_ERR_NOMEM,
                                    "strand spacing: out of memory");
            }
            e = grown;
            cap *= 2;
          }
          e[n].key = cell_key(x, y, z);
          e[n].segment = sg;
          n++;
        }
  }
  qsort(e, n, sizeof *e, cmp_entry);
  g->cells = e;
  g->n_cells = n;
  return SATF_OK;
}

satf_status satf_import_spacing_widths(const satf_strand_set *s, int threads,
                                       float *width, satf_error *err) {
  int n = satf_strand_set_count(s);
  if (n <= 0)
    return SATF_OK;
  int n_seg = 0, longest = 1;
  for (int i = 0; i < n; i++) {
    int m = satf_strand_set_points(s, i);
    n_seg += m > 1 ? m - 1 : 0;
    longest = m > longest ? m : longest;
  }
  grid g = {.s = s};
  int *owner = malloc((size_t)(n_seg ? n_seg : 1) * sizeof *owner);
  float *a = malloc(3 * (size_t)(n_seg ? n_seg : 1) * sizeof *a);
  float *b = malloc(3 * (size_t)(n_seg ? n_seg : 1) * sizeof *b);
  float *len = malloc((size_t)(n_seg ? n_seg : 1) * sizeof *len);
  int nt = threads > 0 ? threads : satf_cpu_count();
  float **scratch = calloc((size_t)nt, sizeof *scratch);
  float *spacing = malloc((size_t)n * sizeof *spacing);
  satf_status st = SATF_OK;
  for (int t = 0; scratch && t < nt; t++)
    if (!(scratch[t] = malloc((size_t)longest * sizeof(float))))
      st = SATF_ERR_NOMEM;
  if (!owner || !a || !b || !len || !scratch || !spacing || st != SATF_OK) {
    st = satf_error_set(err, SATF_ERR_NOMEM,
                        "strand spacing: out of memory for %d strands", n);
    goto done;
  }
  for (int i = 0, sg = 0; i < n; i++) {
    int m;
    const float *p = satf_strand_set_strand(s, i, &m);
    for (int k = 0; k + 1 < m; k++, sg++) {
      memcpy(a + 3 * (size_t)sg, p + 3 * k, 3 * sizeof(float));
      memcpy(b + 3 * (size_t)sg, p + 3 * (k + 1), 3 * sizeof(float));
      owner[sg] = i;
      float d2 = 0.0f;
      for (int c = 0; c < 3; c++)
        d2 += (p[3 * (k + 1) + c] - p[3 * k + c]) *
              (p[3 * (k + 1) + c] - p[3 * k + c]);
      len[sg] = sqrtf(d2);
    }
  }
  float cell = n_seg > 0 ? median_of(len, n_seg) : 0.0f;
  float lo[3], hi[3];
  satf_strand_set_bounds(s, lo, hi);
  memcpy(g.lo, lo, sizeof lo);
  float diag = sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                     (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                     (hi[2] - lo[2]) * (hi[2] - lo[2]));
  /* no cell finer than the grid's keys can number */
  float floor_cell = diag / (float)AXIS_MAX;
  g.cell = cell > floor_cell ? cell : diag > 0.0f ? diag / 64.0f : 1.0f;
  g.owner = owner;
  g.a = a;
  g.b = b;
  g.spacing = spacing;
  g.scratch = scratch;
  if ((st = build_grid(&g, n_seg, err)) != SATF_OK)
    goto done;
  satf_parallel_for((size_t)n, nt, strand_spacing, &g, NULL, NULL);
  /* width = twice the spacing, the density's convention (a strand fills
   * the gap to its neighbour: import_density.c), between a quarter and
   * twice the hairstyle's median so that strands which touch (at a tie)
   * or stray do not become threads or sheets */
  int known = 0;
  for (int i = 0; i < n; i++)
    if (spacing[i] < FLT_MAX)
      len[known++] = spacing[i];
  float med = known > 0 ? 2.0f * median_of(len, known)
                        : (diag > 0.0f ? diag / 100.0f : 1.0f);
  for (int i = 0; i < n; i++) {
    float w = spacing[i] < FLT_MAX ? 2.0f * spacing[i] : med;
    width[i] = w < 0.25f * med ? 0.25f * med : w > 2.0f * med ? 2.0f * med : w;
  }
done:
  for (int t = 0; scratch && t < nt; t++)
    free(scratch[t]);
  free(scratch);
  free((void *)g.cells);
  free(owner);
  free(a);
  free(b);
  free(len);
  free(spacing);
  return st;
}
