/* sector.h - generalized sectors (SATF paper sec. 3.2-3.3): a 2-D annular
 * region of a cluster's cross-section (a track between two radii, a span of
 * phase) carrying a hair density field on a grid in its (s, t) coordinates.
 *
 * Coordinates. The sector lies in its own plane, centred on the +x axis:
 * a point (s, t) in [0,1]^2 sits at radius r = r_inner + s (r_outer -
 * r_inner) and phase phi = (t - 0.5) * phase_span, i.e. at
 * (r cos phi, r sin phi). s runs from the cluster's core outwards, t along
 * the track in the direction of increasing cluster phase u. Grid node
 * (i, j), i < ns, j < nt, sits at s = i / (ns - 1), t = j / (nt - 1) and is
 * stored at density[j * ns + i].
 *
 * Density is hair coverage: the sum of one circular Gaussian per strand
 * cross-section, each of mass pi * sigma^2 (so a lone strand peaks at 0.5
 * and an area tiled by strands has density ~1). */
#ifndef SATF_SECTOR_H
#define SATF_SECTOR_H

#include <stdint.h>

#include "satf/satf.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct satf_sector_shape {
  float r_inner;    /* inner radius of the track, in sector units */
  float r_outer;    /* outer radius of the track */
  float phase_span; /* angular width of the sector, radians */
} satf_sector_shape;

/* The canonical shape used by the default database: a track one fifth of
 * the cluster radius deep and 1/16 of the circle wide. */
satf_sector_shape satf_sector_shape_default(void);
satf_status satf_sector_shape_check(const satf_sector_shape *shape,
                                    satf_error *err);

typedef struct satf_sector {
  satf_sector_shape shape;
  int ns, nt;         /* grid nodes along s and t (>= 2 each) */
  float strand_sigma; /* Gaussian width of the strands, sector units */
  float *density;     /* ns * nt values, owned */
  float *node_xy;     /* plane positions of the grid nodes, 2*ns*nt, owned */
} satf_sector;

/* Allocates an empty (zero-density) sector. */
satf_status satf_sector_create(const satf_sector_shape *shape, int ns, int nt,
                               float strand_sigma, satf_sector **out,
                               satf_error *err);
void satf_sector_destroy(satf_sector *sector);

/* Extent [lo, hi] of the sector shape projected on the unit axis e. */
void satf_sector_extent(const satf_sector_shape *shape, const float e[2],
                        float *lo, float *hi);

/* Position of the point (s, t) in the sector plane. */
void satf_sector_point(const satf_sector_shape *shape, float s, float t,
                       float xy[2]);
/* Inverse of satf_sector_point; returns 0 when xy is outside the sector. */
int satf_sector_param(const satf_sector_shape *shape, const float xy[2],
                      float st[2]);

/* Adds one strand's circular Gaussian centred at (s, t) (SATF sec. 3.3). */
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
} satf_sector_recipe;

/* Draws a recipe for sample `index` of database seed `seed`. Covers empty to
 * dense, even to very uneven sectors. Depends only on (seed, index). */
void satf_sector_recipe_random(uint64_t seed, uint64_t index,
                               satf_sector_recipe *recipe);
/* Places the recipe's strands (seeded by (seed, index)) into sector, which
 * must be empty. */
void satf_sector_fill(satf_sector *sector, const satf_sector_recipe *recipe,
                      uint64_t seed, uint64_t index);

#ifdef __cplusplus
}
#endif
#endif
