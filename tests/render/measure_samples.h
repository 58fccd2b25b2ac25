/* measure_samples.h - a growing list of measured values and their sort,
 * for the measuring programs (measure_tracks, measure_db_range). */
#ifndef MEASURE_SAMPLES_H
#define MEASURE_SAMPLES_H

#include <stdlib.h>

typedef struct {
  float *v;
  size_t n, cap;
} samples;

/* Appends v; a program that runs out of memory stops (exit 2). */
static inline void push(samples *s, float v) {
  if (s->n == s->cap) {
    s->cap = s->cap ? 2 * s->cap : 1024;
    s->v = realloc(s->v, s->cap * sizeof(float));
    if (!s->v)
      exit(2);
  }
  s->v[s->n++] = v;
}

static inline int samples_cmp(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

/* Ascending. */
static inline void samples_sort(samples *s) {
  qsort(s->v, s->n, sizeof(float), samples_cmp);
}

#endif
