/* offline.h - the offline database build (offline/, SATF sec. 3.3, 5):
 * generalized sectors with their density grids and random recipes, planar
 * ray tracing of HRIRs (eq. 5), and the multi-threaded build of a whole
 * database. The record contract it honours (sector shape, trace parameters,
 * extents) belongs to the database and is declared in satf/db.h. */
#ifndef SATF_OFFLINE_H
#define SATF_OFFLINE_H

#include <stdint.h>

#include "satf/db.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Generalized sectors with a density grid (SATF sec. 3.2-3.3); the shape
 * and coordinates are the record contract in satf/db.h. */

typedef struct satf_sector {
  satf_sector_shape shape;
  int ns, nt;         /* grid nodes along s and t (>= 2 each) */
  float strand_sigma; /* Gaussian width of the strands, sector units */
  float *density;     /* ns * nt values, owned */
  float *node_xy;     /* plane positions of the grid nodes, 2*ns*nt, owned */
  /* The strands as fibres with circular cross-sections, for the fibre
   * tracer (offline/trace_fiber.c): 3 values each, the plane position of
   * the strand's centre and its radius = strand_sigma (a disc of radius
   * sigma covers pi sigma^2, the mass of the strand's density). */
  int fiber_count, fiber_cap;
  float *fibers;    /* 3 * fiber_count values, owned */
  int fiber_failed; /* a fibre could not be stored (out of memory) */
} satf_sector;

/* Allocates an empty (zero-density) sector. */
satf_status satf_sector_create(const satf_sector_shape *shape, int ns, int nt,
                               float strand_sigma, satf_sector **out,
                               satf_error *err);
void satf_sector_destroy(satf_sector *sector);

/* Position of the point (s, t) in the sector plane. */
void satf_sector_point(const satf_sector_shape *shape, float s, float t,
                       float xy[2]);
/* Inverse of satf_sector_point; returns 0 when xy is outside the sector. */
int satf_sector_param(const satf_sector_shape *shape, const float xy[2],
                      float st[2]);

/* Adds one strand's circular Gaussian centred at (s, t) (SATF sec. 3.3),
 * and the strand to the fibre list. */
void satf_sector_add_strand(satf_sector *sector, float s, float t);
/* Multiplies every density value by k. */
void satf_sector_scale(satf_sector *sector, float k);

/* Bilinear density at (s, t); 0 outside [0,1]^2. */
float satf_sector_density(const satf_sector *sector, float s, float t);

typedef enum satf_layout {
  SATF_LAYOUT_UNIFORM = 0,
  SATF_LAYOUT_CLUMPED,
  SATF_LAYOUT_GRADIENT_S,
  SATF_LAYOUT_GRADIENT_T,
  SATF_LAYOUT_HOLES,
  SATF_LAYOUT_COUNT
} satf_layout;

const char *satf_layout_name(satf_layout layout);

/* The random control parameters of one sector (SATF sec. 5). */
typedef struct satf_sector_recipe {
  satf_layout layout;
  int strands;
  float strand_sigma;
  float param[4]; /* layout-specific: clump count/spread, slope, holes */
  /* The layout spans the sector grown by margin x strand_sigma on every
   * side; a strand whose centre falls outside the sector adds its density
   * tail but no fibre (its fibre belongs to the neighbouring sector, as
   * in a cluster's shells). 0: every strand inside. */
  float margin;
} satf_sector_recipe;

/* What random recipes are drawn from. */
typedef struct satf_sector_ranges {
  double sigma_lo, sigma_hi; /* strand_sigma, uniform, sector units */
  float margin;              /* the recipes' margin */
} satf_sector_ranges;

/* The ranges of a build of records of `kind`: sigma 0.008..0.02 for both;
 * no margin for Phong (the paper's sectors), 3 for fibre records, measured
 * to cover the density features of imported hair's shells
 * (tests/render/measure_db_range). */
satf_sector_ranges satf_sector_ranges_default(satf_record_kind kind);

/* Draws a recipe for sample `index` of database seed `seed` from `ranges`.
 * Covers empty to dense, even to very uneven sectors. Depends only on
 * (seed, index, ranges). */
void satf_sector_recipe_draw(uint64_t seed, uint64_t index,
                             const satf_sector_ranges *ranges,
                             satf_sector_recipe *recipe);
/* satf_sector_recipe_draw from the Phong ranges. */
void satf_sector_recipe_random(uint64_t seed, uint64_t index,
                               satf_sector_recipe *recipe);
/* Places the recipe's strands (seeded by (seed, index)) into sector, which
 * must be empty. */
void satf_sector_fill(satf_sector *sector, const satf_sector_recipe *recipe,
                      uint64_t seed, uint64_t index);

/* Eq. 5: one front-to-back step. Updates the ray's accumulated reflectance
 * and opacity with a sample of opacity alpha and reflectance re. */
void satf_accumulate(float *acc_re, float *acc_alpha, float alpha, float re);

/* Opacity of a march step of length ds through density rho. */
float satf_step_opacity(float extinction, float rho, float ds);

/* Phong reflectance of a point with (unnormalised) normal n, light and view
 * directions l, v (unit, in the plane), lit by transmittance T. */
float satf_phong(const satf_trace_params *p, const float n[2], const float l[2],
                 const float v[2], float transmittance);

/* Traces one HRIR: re[width] and alpha[width]. */
satf_status satf_trace_hrir(const satf_sector *sector,
                            const satf_trace_params *p, float theta_v,
                            float theta_l, float *re, float *alpha,
                            satf_error *err);

/* Traces the HRIRs of every view x light pair on uniform grids of n_view and
 * n_light azimuths (k * 2 pi / n). Output record (iv, il) starts at
 * ((iv * n_light) + il) * width in re and alpha. Reuses work shared by the
 * pairs; equal, value for value, to calling satf_trace_hrir per pair. */
satf_status satf_trace_all(const satf_sector *sector,
                           const satf_trace_params *p, int n_view, int n_light,
                           float *re, float *alpha, satf_error *err);

/* Fibre records (format version 2, offline/trace_fiber.c; satf/db.h
 * "Record kinds"): 2-D Monte Carlo path tracing of the sector's fibres
 * (sector->fibers) under every view x light azimuth pair of uniform grids
 * (k * 2 pi / n). Writes n_view x n_light records of
 * SATF_DB_FIBER_CHANNELS(p->levels) x width values to out, record (iv, il)
 * at (iv * n_light + il) * channels * width, channel-major (SATF_DB_CH_*).
 * Sample j of view iv draws its random numbers from stream (sample, iv, j)
 * of `seed` only, so records do not depend on threads or call order. */
satf_status satf_trace_fiber_all(const satf_sector *sector,
                                 const satf_fiber_trace_params *p, int width,
                                 int n_view, int n_light, uint64_t seed,
                                 uint64_t sample, float *out, satf_error *err);

/* ---- Builds ----
 * building an HRIR database (SATF sec. 5): random generalized
 * sectors, planar ray traced under every view x light azimuth pair. */

/* Called on the calling thread about every 100 ms with samples done. */
typedef void (*satf_build_progress)(void *ctx, size_t done, size_t total);

/* Builds and finalizes a database on `threads` threads (0 = all cores).
 * Sample i depends only on (p->seed, i), so the result is bit-identical for
 * any thread count. */
satf_status satf_build(const satf_build_params *p, int threads,
                       satf_build_progress progress, void *progress_ctx,
                       satf_db **out, satf_error *err);

/* Builds samples [first, first + count) of the build p into rec and
 * features (the part layout of satf/db.h: satf_db_sample_floats values and
 * SATF_FEATURES features per sample, values rounded to half floats). The
 * values are those satf_build stores for these samples: a build may be cut
 * into ranges made anywhere (MPI ranks, shards). */
satf_status satf_build_range(const satf_build_params *p, int first, int count,
                             int threads, satf_build_progress progress,
                             void *progress_ctx, float *rec, float *features,
                             satf_error *err);

/* Builds part I of N of the build p (satf_db_part_range); destroy with
 * satf_db_part_destroy. */
satf_status satf_build_part(const satf_build_params *p, int index, int parts,
                            int threads, satf_build_progress progress,
                            void *progress_ctx, satf_db_part **out,
                            satf_error *err);

/* The sector of sample i of a build (for tests and held-out checks);
 * destroy with satf_sector_destroy. */
satf_status satf_build_sector(const satf_build_params *p, uint64_t seed,
                              uint64_t index, satf_sector **out,
                              satf_error *err);

#ifdef __cplusplus
}
#endif
#endif
