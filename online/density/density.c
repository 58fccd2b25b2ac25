/* density.c - see density.h. */
#include "satf/density.h"
#include "satf/math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "satf/db.h"
#include "tracks.h"

/* The largest feature grid satf_sector_features_grid takes (stack). */
#define SATF_SECTOR_GRID_MAX 64

struct satf_strands {
  int n;
  float sigma, scale;
  float *base;   /* n x 2: position at t = 0.5 */
  float *wobble; /* n x 4: amplitude x, amplitude y, frequency, phase */
  /* bucket grid over [-1.1, 1.1]^2 of base positions, for density queries */
  int cells;
  float cell;
  int *start, *items;
  density_tracks *tracks; /* type "tracks": the cluster's own strands */
};

/* Strands drift at most this far (normalised units) from their base. */
#define WOBBLE 0.04f

static void disk_uniform(satf_rng *rng, float xy[2]) {
  float r = sqrtf((float)satf_rng_uniform(rng));
  float a = SATF_TWO_PI_F * (float)satf_rng_uniform(rng);
  xy[0] = r * cosf(a);
  xy[1] = r * sinf(a);
}

static void place(const satf_scene_density *d, satf_rng *rng,
                  const float (*centres)[2], float xy[2]) {
  switch (d->layout) {
  case SATF_SCENE_LAYOUT_CLUMPED: {
    int c = (int)satf_rng_below(rng, (uint32_t)(d->clumps > 0 ? d->clumps : 1));
    for (int tries = 0; tries < 16; tries++) {
      xy[0] = centres[c][0] + d->clump_spread * (float)satf_rng_normal(rng);
      xy[1] = centres[c][1] + d->clump_spread * (float)satf_rng_normal(rng);
      if (xy[0] * xy[0] + xy[1] * xy[1] <= 1.0f)
        return;
    }
    disk_uniform(rng, xy);
    return;
  }
  case SATF_SCENE_LAYOUT_GRADIENT: {
    /* radial pdf proportional to r (1 + g (r - 1/2)), by rejection */
    float g = d->gradient;
    for (;;) {
      disk_uniform(rng, xy);
      float r = sqrtf(xy[0] * xy[0] + xy[1] * xy[1]);
      float w = (1.0f + g * (r - 0.5f)) / (1.0f + fabsf(g) * 0.5f);
      if ((float)satf_rng_uniform(rng) < w)
        return;
    }
  }
  case SATF_SCENE_LAYOUT_HOLES:
    for (int tries = 0; tries < 64; tries++) {
      disk_uniform(rng, xy);
      int inside = 0;
      for (int h = 0; h < d->holes && h < 16; h++) {
        float dx = xy[0] - centres[h][0], dy = xy[1] - centres[h][1];
        inside |= dx * dx + dy * dy < d->hole_radius * d->hole_radius;
      }
      if (!inside)
        return;
    }
    return;
  default: disk_uniform(rng, xy);
  }
}

satf_status satf_strands_create(const satf_scene_density *d, satf_strands **out,
                                satf_error *err) {
  *out = NULL;
  if (d->type == SATF_SCENE_DENSITY_TRACKS) {
    satf_strands *s = calloc(1, sizeof *s);
    if (!s)
      return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
    satf_status st = density_tracks_create(d, &s->tracks, err);
    if (st != SATF_OK) {
      free(s);
      return st;
    }
    s->n = density_tracks_count(s->tracks);
    *out = s;
    return SATF_OK;
  }
  if (d->strands < 0 || d->strands > 10000000 || !(d->strand_width > 0.0f))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "procedural density: %d strands of width %g",
                          d->strands, (double)d->strand_width);
  satf_strands *s = calloc(1, sizeof *s);
  if (!s)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  s->n = d->strands;
  s->sigma = 0.5f * d->strand_width; /* width is a diameter */
  s->scale = d->scale;
  size_t n = (size_t)(s->n > 0 ? s->n : 1);
  s->base = malloc(2 * n * sizeof(float));
  s->wobble = malloc(4 * n * sizeof(float));
  s->cell = 4.0f * s->sigma + 2.0f * WOBBLE;
  if (s->cell < 2.2f / 256.0f)
    s->cell = 2.2f / 256.0f;
  s->cells = (int)ceilf(2.2f / s->cell);
  s->start = calloc((size_t)s->cells * s->cells + 1, sizeof(int));
  s->items = malloc(n * sizeof(int));
  if (!s->base || !s->wobble || !s->start || !s->items) {
    satf_strands_destroy(s);
    return satf_error_set(err, SATF_ERR_NOMEM, "cannot allocate %d strands",
                          d->strands);
  }
  satf_rng rng;
  satf_rng_seed(&rng, d->seed, 0x57A2D5);
  float centres[16][2];
  for (int c = 0; c < 16; c++)
    disk_uniform(&rng, centres[c]);
  for (int i = 0; i < s->n; i++) {
    place(d, &rng, (const float(*)[2])centres, s->base + 2 * i);
    float *w = s->wobble + 4 * i;
    w[0] = WOBBLE * (float)satf_rng_range(&rng, -1, 1);
    w[1] = WOBBLE * (float)satf_rng_range(&rng, -1, 1);
    w[2] = (float)satf_rng_range(&rng, 0.5, 2.0);
    w[3] = (float)satf_rng_range(&rng, 0, SATF_TWO_PI_F);
  }
  /* counting sort of strands into buckets by base position */
  int *cellof = malloc(n * sizeof(int));
  if (!cellof) {
    satf_strands_destroy(s);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  for (int i = 0; i < s->n; i++) {
    int cx = (int)((s->base[2 * i] + 1.1f) / s->cell);
    int cy = (int)((s->base[2 * i + 1] + 1.1f) / s->cell);
    cx = cx < 0 ? 0 : cx >= s->cells ? s->cells - 1 : cx;
    cy = cy < 0 ? 0 : cy >= s->cells ? s->cells - 1 : cy;
    cellof[i] = cy * s->cells + cx;
    s->start[cellof[i] + 1]++;
  }
  for (int c = 0; c < s->cells * s->cells; c++)
    s->start[c + 1] += s->start[c];
  int *fill = calloc((size_t)s->cells * s->cells, sizeof(int));
  if (!fill) {
    free(cellof);
    satf_strands_destroy(s);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  for (int i = 0; i < s->n; i++)
    s->items[s->start[cellof[i]] + fill[cellof[i]]++] = i;
  free(fill);
  free(cellof);
  *out = s;
  return SATF_OK;
}

void satf_strands_destroy(satf_strands *s) {
  if (s) {
    density_tracks_destroy(s->tracks);
    free(s->base);
    free(s->wobble);
    free(s->start);
    free(s->items);
    free(s);
  }
}

int satf_strands_count(const satf_strands *s) { return s->n; }

void satf_strands_position(const satf_strands *s, int i, float t, float xy[2]) {
  if (s->tracks) {
    density_tracks_position(s->tracks, i, t, xy);
    return;
  }
  const float *w = s->wobble + 4 * i;
  float k = sinf(SATF_TWO_PI_F * w[2] * t + w[3]);
  xy[0] = s->base[2 * i] + w[0] * k;
  xy[1] = s->base[2 * i + 1] + w[1] * k;
}

/* SATF sec. 3.3: the density is the sum of one circular Gaussian per strand
 * cross-section; peak 1/2 as in the database (see satf/sector.h). */
static float bucket_density(const satf_strands *s, const int *start, int cells,
                            float cell, const float *pos, float t, float x,
                            float y);

float satf_strands_density(const satf_strands *s, float t, float x, float y) {
  if (s->tracks)
    return density_tracks_density(s->tracks, t, x, y);
  return bucket_density(s, s->start, s->cells, s->cell, NULL, t, x, y);
}

/* The sum above over the strands in the 3 x 3 buckets (start: the first
 * of each of cells x cells buckets of side cell over [-1.1, 1.1]^2) about
 * (x, y); pos: the strands' positions at t in bucket order (strands_slice,
 * a fine slice), or NULL to compute them here from the base buckets. */
static float bucket_density(const satf_strands *s, const int *start, int cells,
                            float cell, const float *pos, float t, float x,
                            float y) {
  float cut = 4.0f * s->sigma, inv = 1.0f / (2.0f * s->sigma * s->sigma);
  int cx = (int)((x + 1.1f) / cell), cy = (int)((y + 1.1f) / cell);
  float sum = 0.0f;
  for (int by = cy - 1; by <= cy + 1; by++) {
    if (by < 0 || by >= cells)
      continue;
    for (int bx = cx - 1; bx <= cx + 1; bx++) {
      if (bx < 0 || bx >= cells)
        continue;
      int c = by * cells + bx;
      for (int k = start[c]; k < start[c + 1]; k++) {
        float q[2];
        const float *p = pos ? pos + 2 * (size_t)k : q;
        if (!pos)
          satf_strands_position(s, s->items[k], t, q);
        float dx = x - p[0], dy = y - p[1], d2 = dx * dx + dy * dy;
        if (d2 < cut * cut)
          sum += 0.5f * expf(-d2 * inv);
      }
    }
  }
  return sum * s->scale;
}

/* Every procedural strand's position at t, in bucket order, for the many
 * density queries of one t slice (a sine per strand once instead of per
 * query); NULL for tracks, for more strands than are worth a copy per
 * thread, or without memory (queries then compute them). */
static float *strands_slice(const satf_strands *s, float t) {
  if (s->tracks || s->n <= 0 || s->n > (1 << 20))
    return NULL;
  float *pos = malloc(2 * (size_t)s->n * sizeof(float));
  if (pos)
    for (int k = 0; k < s->n; k++)
      satf_strands_position(s, s->items[k], t, pos + 2 * k);
  return pos;
}

/* Past 1M strands, positions copied per slice but queried through the
 * base-position buckets above scan every strand within 4 sigma + 2 WOBBLE
 * of a query: 10M strands of width 0.01 took minutes to set up. A slice's
 * positions at t bucketed anew, in cells of 4 sigma (at most FINE_CELLS a
 * side), reach only the strands that can count: the same sum. */
#define FINE_CELLS 2048

typedef struct fine_slice {
  int cells;
  float cell;
  int *start;
  float *pos; /* bucket order */
} fine_slice;

static int fine_cell(const fine_slice *f, const float p[2]) {
  int cx = (int)((p[0] + 1.1f) / f->cell), cy = (int)((p[1] + 1.1f) / f->cell);
  cx = cx < 0 ? 0 : cx >= f->cells ? f->cells - 1 : cx;
  cy = cy < 0 ? 0 : cy >= f->cells ? f->cells - 1 : cy;
  return cy * f->cells + cx;
}

static void fine_slice_free(fine_slice *f) {
  free(f->start);
  free(f->pos);
  memset(f, 0, sizeof *f);
}

/* 0, or -1 without memory (queries then take the slow path). */
static int fine_slice_build(const satf_strands *s, float t, fine_slice *f) {
  memset(f, 0, sizeof *f);
  f->cell = 4.0f * s->sigma;
  if (f->cell < 2.2f / FINE_CELLS)
    f->cell = 2.2f / FINE_CELLS;
  f->cells = (int)ceilf(2.2f / f->cell);
  size_t nc = (size_t)f->cells * (size_t)f->cells;
  f->start = calloc(nc + 1, sizeof(int));
  f->pos = malloc(2 * (size_t)s->n * sizeof(float));
  int *at = malloc(nc * sizeof(int));
  if (!f->start || !f->pos || !at) {
    free(at);
    fine_slice_free(f);
    return -1;
  }
  float q[2];
  for (int i = 0; i < s->n; i++) {
    satf_strands_position(s, i, t, q);
    f->start[fine_cell(f, q) + 1]++;
  }
  for (size_t c = 0; c < nc; c++)
    f->start[c + 1] += f->start[c];
  memcpy(at, f->start, nc * sizeof(int));
  for (int i = 0; i < s->n; i++) {
    satf_strands_position(s, i, t, q);
    int k = at[fine_cell(f, q)]++;
    f->pos[2 * (size_t)k] = q[0];
    f->pos[2 * (size_t)k + 1] = q[1];
  }
  free(at);
  return 0;
}

typedef struct features_job {
  const satf_cluster *cluster;
  const satf_shell_params *shell;
  const satf_strands *strands;
  const satf_vdb_grid *vdb;
  const float *m;
  int grid; /* nodes per side */
  float *features;
} features_job;

static void transform_point(const float *m, const float p[3], float out[3]) {
  for (int r = 0; r < 3; r++)
    out[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] +
             m[4 * r + 3];
}

/* One t slice: every sector (i, k, j) of every layer and phase. */
static int features_slice(void *vctx, size_t i, int thread) {
  (void)thread;
  const features_job *job = vctx;
  const satf_shell_params *sh = job->shell;
  float t = (float)i / (float)sh->st;
  const int G = job->grid;
  float dens[SATF_SECTOR_GRID_MAX * SATF_SECTOR_GRID_MAX];
  satf_cluster_section sec;
  float *pos = NULL;
  fine_slice fine = {0};
  if (job->vdb)
    satf_cluster_section_at(job->cluster, t, &sec);
  else if (!job->strands->tracks && job->strands->n > (1 << 20))
    fine_slice_build(job->strands, t, &fine);
  else
    pos = strands_slice(job->strands, t);
  for (int k = 0; k < sh->layers; k++) {
    float v0 = satf_shell_layer_v(sh, k), v1 = satf_shell_layer_v(sh, k + 1);
    for (int j = 0; j < sh->su; j++) {
      float u0 = SATF_TWO_PI_F * (float)j / (float)sh->su;
      float du = SATF_TWO_PI_F / (float)sh->su;
      for (int b = 0; b < G; b++) { /* t of the sector: along the phase */
        float u = u0 + du * (float)b / (float)(G - 1);
        for (int a = 0; a < G; a++) { /* s of the sector: along the radius */
          float v = v0 + (v1 - v0) * (float)a / (float)(G - 1);
          float d;
          if (job->vdb) {
            float p[3], w[3];
            satf_cluster_section_point(&sec, v, u, p);
            if (job->m)
              transform_point(job->m, p, w);
            else
              memcpy(w, p, sizeof w);
            d = satf_vdb_sample(job->vdb, w);
          } else {
            /* the strands live at (v cos u, v sin u) in the ellipse's own
             * axes, which the twist turns (SATF eq. 1, satf/geometry.h):
             * they turn with the cross-section at no cost here */
            float x = v * cosf(u), y = v * sinf(u);
            const satf_strands *st = job->strands;
            d = fine.pos ? bucket_density(st, fine.start, fine.cells, fine.cell,
                                          fine.pos, t, x, y)
                : pos ? bucket_density(st, st->start, st->cells, st->cell, pos,
                                       t, x, y)
                      : satf_strands_density(st, t, x, y);
          }
          dens[b * G + a] = d;
        }
      }
      float *f =
          job->features + (((size_t)i * sh->layers + k) * sh->su + j) * 3;
      satf_density_features(dens, G, G, f); /* SATF sec. 5.2 */
    }
  }
  free(pos);
  fine_slice_free(&fine);
  return 0;
}

satf_status satf_sector_features_grid(const satf_cluster *cluster,
                                      const satf_shell_params *shell,
                                      const satf_strands *strands,
                                      const satf_vdb_grid *vdb,
                                      const float *instance, int grid,
                                      int threads, float *features,
                                      satf_error *err) {
  if (!strands && !vdb)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "sector features need strands or a VDB grid");
  if (grid < 2 || grid > SATF_SECTOR_GRID_MAX)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "sector feature grid of %d nodes: 2 to %d", grid,
                          SATF_SECTOR_GRID_MAX);
  features_job job = {cluster, shell, strands, vdb, instance, grid, features};
  if (satf_parallel_for((size_t)shell->st + 1, threads, features_slice, &job,
                        NULL, NULL) != 0)
    return satf_error_set(err, SATF_ERR_INTERNAL, "feature computation failed");
  return SATF_OK;
}

satf_status satf_sector_features(const satf_cluster *cluster,
                                 const satf_shell_params *shell,
                                 const satf_strands *strands,
                                 const satf_vdb_grid *vdb,
                                 const float *instance, int threads,
                                 float *features, satf_error *err) {
  return satf_sector_features_grid(cluster, shell, strands, vdb, instance,
                                   SATF_SECTOR_GRID, threads, features, err);
}
