/* tracks.c - see tracks.h. */
#include "tracks.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The bucket grids cover [-BOX, BOX]^2 of the normalised cross-section
 * (the shells lie within the unit disk; strands just outside still reach
 * in with their Gaussian's tail). */
#define BOX 1.1f
#define MAX_CELLS 48

struct density_tracks {
  int n, slices;
  float sigma, scale;
  int *first, *count; /* copies: an animation's scenes come and go */
  size_t *offset;     /* n: index of track k's first pair */
  float *xy;
  /* per slice interval i (between slice i and i + 1): a bucket grid of
   * the tracks present at either end, each in every cell its segment's
   * box (grown by the Gaussian's cut-off) touches */
  int cells;
  float cell;
  size_t *start; /* (slices - 1) * cells^2 + 1 */
  int *items;
};

/* Track k at slice i, or NULL when the strand does not reach it. */
static const float *at_slice(const density_tracks *t, int k, int i) {
  int j = i - t->first[k];
  if (j < 0 || j >= t->count[k])
    return NULL;
  return t->xy + 2 * (t->offset[k] + (size_t)j);
}

static int cell_of(const density_tracks *t, float v) {
  int c = (int)floorf((v + BOX) / t->cell);
  return c < 0 ? 0 : c >= t->cells ? t->cells - 1 : c;
}

/* Calls fn(ctx, cell) for every cell track k's interval-i box touches;
 * returns 0 when the track is absent from the interval. */
static int for_cells(const density_tracks *t, int k, int i,
                     void (*fn)(void *, size_t), void *ctx) {
  const float *a = at_slice(t, k, i), *b = at_slice(t, k, i + 1);
  if (!a && !b)
    return 0;
  if (!a)
    a = b;
  if (!b)
    b = a;
  float cut = 4.0f * t->sigma;
  int x0 = cell_of(t, fminf(a[0], b[0]) - cut);
  int x1 = cell_of(t, fmaxf(a[0], b[0]) + cut);
  int y0 = cell_of(t, fminf(a[1], b[1]) - cut);
  int y1 = cell_of(t, fmaxf(a[1], b[1]) + cut);
  size_t base = (size_t)i * (size_t)t->cells * (size_t)t->cells;
  for (int y = y0; y <= y1; y++)
    for (int x = x0; x <= x1; x++)
      fn(ctx, base + (size_t)y * (size_t)t->cells + (size_t)x);
  return 1;
}

static void count_cell(void *ctx, size_t c) { ((size_t *)ctx)[c + 1]++; }

typedef struct fill_ctx {
  density_tracks *t;
  size_t *next;
  int k;
} fill_ctx;

static void fill_cell(void *vctx, size_t c) {
  fill_ctx *f = vctx;
  f->t->items[f->next[c]++] = f->k;
}

satf_status density_tracks_create(const satf_scene_density *d,
                                  density_tracks **out, satf_error *err) {
  *out = NULL;
  if (d->track_slices < 2 || d->n_tracks < 0 || !(d->strand_width > 0.0f))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "tracks density: %d tracks over %d slices, width %g",
                          d->n_tracks, d->track_slices,
                          (double)d->strand_width);
  density_tracks *t = calloc(1, sizeof *t);
  if (!t)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  t->n = d->n_tracks;
  t->slices = d->track_slices;
  t->sigma = 0.5f * d->strand_width; /* width is a diameter */
  t->scale = d->scale;
  /* cells about the Gaussian's reach, at most MAX_CELLS a side */
  t->cell = fmaxf(4.0f * t->sigma, 2.0f * BOX / (float)MAX_CELLS);
  t->cells = (int)ceilf(2.0f * BOX / t->cell);
  if (t->cells > MAX_CELLS)
    t->cells = MAX_CELLS;
  t->cell = 2.0f * BOX / (float)t->cells;
  size_t ncell = (size_t)(t->slices - 1) * (size_t)t->cells * (size_t)t->cells;
  t->offset = malloc(((size_t)t->n + 1) * sizeof *t->offset);
  t->start = calloc(ncell + 1, sizeof *t->start);
  t->first = malloc(((size_t)t->n + 1) * sizeof(int));
  t->count = malloc(((size_t)t->n + 1) * sizeof(int));
  if (!t->offset || !t->start || !t->first || !t->count) {
    density_tracks_destroy(t);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot allocate the tracks of %d strands", t->n);
  }
  size_t at = 0;
  for (int k = 0; k < t->n; k++) {
    t->first[k] = d->track_first[k];
    t->count[k] = d->track_count[k];
    t->offset[k] = at;
    at += (size_t)t->count[k];
  }
  t->xy = malloc((2 * at + 1) * sizeof(float));
  if (!t->xy) {
    density_tracks_destroy(t);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot allocate the tracks of %d strands",
                          d->n_tracks);
  }
  if (at > 0)
    memcpy(t->xy, d->track_xy, 2 * at * sizeof(float));
  /* counting sort into the cells of every interval */
  for (int k = 0; k < t->n; k++)
    for (int i = t->first[k] - 1; i < t->first[k] + t->count[k]; i++)
      if (i >= 0 && i < t->slices - 1)
        for_cells(t, k, i, count_cell, t->start);
  for (size_t c = 0; c < ncell; c++)
    t->start[c + 1] += t->start[c];
  size_t *next = malloc((ncell + 1) * sizeof *next);
  t->items = malloc((t->start[ncell] + 1) * sizeof *t->items);
  if (!next || !t->items) {
    free(next);
    density_tracks_destroy(t);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot allocate the tracks of %d strands", t->n);
  }
  memcpy(next, t->start, (ncell + 1) * sizeof *next);
  fill_ctx f = {t, next, 0};
  for (f.k = 0; f.k < t->n; f.k++)
    for (int i = t->first[f.k] - 1; i < t->first[f.k] + t->count[f.k]; i++)
      if (i >= 0 && i < t->slices - 1)
        for_cells(t, f.k, i, fill_cell, &f);
  free(next);
  *out = t;
  return SATF_OK;
}

void density_tracks_destroy(density_tracks *t) {
  if (t) {
    free(t->offset);
    free(t->start);
    free(t->first);
    free(t->count);
    free(t->xy);
    free(t->items);
    free(t);
  }
}

int density_tracks_count(const density_tracks *t) { return t->n; }

/* The slice interval of t and the fraction along it. */
static int interval(const density_tracks *t, float t_along, float *f) {
  float g = fminf(fmaxf(t_along, 0.0f), 1.0f) * (float)(t->slices - 1);
  int i = (int)floorf(g);
  if (i > t->slices - 2)
    i = t->slices - 2;
  *f = g - (float)i;
  return i;
}

void density_tracks_position(const density_tracks *t, int k, float t_along,
                             float xy[2]) {
  float f;
  int i = interval(t, t_along, &f);
  int lo = t->first[k], hi = t->first[k] + t->count[k] - 1;
  if (i < lo) { /* before the root: held at the root */
    memcpy(xy, at_slice(t, k, lo), 2 * sizeof(float));
    return;
  }
  if (i >= hi) { /* past the tip: held at the tip */
    memcpy(xy, at_slice(t, k, hi), 2 * sizeof(float));
    return;
  }
  const float *a = at_slice(t, k, i), *b = at_slice(t, k, i + 1);
  xy[0] = a[0] + f * (b[0] - a[0]);
  xy[1] = a[1] + f * (b[1] - a[1]);
}

float density_tracks_density(const density_tracks *t, float t_along, float x,
                             float y) {
  if (t->n == 0)
    return 0.0f;
  float f;
  int i = interval(t, t_along, &f);
  float cut2 = 16.0f * t->sigma * t->sigma;
  float inv = 1.0f / (2.0f * t->sigma * t->sigma);
  size_t c = (size_t)i * (size_t)t->cells * (size_t)t->cells +
             (size_t)cell_of(t, y) * (size_t)t->cells + (size_t)cell_of(t, x);
  float sum = 0.0f;
  for (size_t q = t->start[c]; q < t->start[c + 1]; q++) {
    int k = t->items[q];
    const float *a = at_slice(t, k, i), *b = at_slice(t, k, i + 1);
    float p[2], w = 1.0f;
    if (a && b) {
      p[0] = a[0] + f * (b[0] - a[0]);
      p[1] = a[1] + f * (b[1] - a[1]);
    } else if (a) { /* the tip lies in this interval: fades out along it */
      p[0] = a[0];
      p[1] = a[1];
      w = 1.0f - f;
    } else { /* the root lies in this interval: fades in */
      p[0] = b[0];
      p[1] = b[1];
      w = f;
    }
    float dx = x - p[0], dy = y - p[1], d2 = dx * dx + dy * dy;
    if (d2 < cut2)
      sum += w * 0.5f * expf(-d2 * inv); /* SATF sec. 3.3, as density.c */
  }
  return sum * t->scale;
}
