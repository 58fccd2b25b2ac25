/* maps.h - the SATF step of the online phase (SATF sec. 6.2, eq. 6-7, 12):
 * per frame, every HSV of a cluster's shells gets its reflectance and alpha
 * from database look-ups, laid out as a texture per layer (re-map,
 * alpha-map), plus the self-shadow sum of the outer layers' alpha (s-map).
 *
 * Texture layout. Layer k of a cluster is an image (su * width) texels wide
 * and 2 * st rows high, 4 floats per texel: reflectance, alpha, the s-map
 * sum of eq. 12, and the HSV's mean density (for the plain mode). HSV
 * (i, k, j) owns columns [j * width, (j + 1) * width) and rows 2i (its
 * boundary sector at t_i) and 2i + 1 (its boundary sector at t_{i+1}), so a
 * bilinear texture fetch at row 2i + 1/2 + g, g = t st - i, interpolates
 * between the two records exactly as eq. 7. Within an HSV, column x
 * (phase fraction f = (x + 1/2) / width across the HSV) shows the record
 * sample whose ray passes through the point at phase f on the layer's outer
 * surface, seen from the sector's view azimuth (the layout of trace.h). */
#ifndef SATF_ONLINE_MAPS_H
#define SATF_ONLINE_MAPS_H

#include "satf/db.h"
#include "satf/geometry.h"

/* Per prototype: the geometry of its boundary sectors and their density
 * features, computed once (they change only with the density). */
typedef struct satf_neighbor_cache satf_neighbor_cache;

typedef struct satf_shell_geom {
  satf_shell_params shell;
  float *frames;   /* per sector (i, k, j): centre P, outward N, phase dir T */
  float *features; /* per sector: 3 density features */
  /* The database samples nearest to every sector's features and to every
   * HSV's averaged features (satf_maps_prepare): they change only with the
   * density, so frames only blend azimuths. NULL: searched per look-up. */
  satf_neighbor_cache *neighbors;
  /* per sector: the unit direction its fibres run in, N x T turned
   * towards the strands' own course within the sector's surface
   * (satf_shell_geom_set_hair); NULL: N x T, the trajectory's */
  float *hair;
  /* new with every new frames, neighbours or hair (satf_shell_geom_create,
   * satf_maps_prepare, satf_shell_geom_set_hair): copies of the geometry that
   * other memory holds (the GPU's, maps_gpu.c) are current while it stays */
  unsigned long serial;
} satf_shell_geom;

satf_status satf_shell_geom_create(const satf_cluster *cluster,
                                   const satf_shell_params *shell,
                                   satf_shell_geom *out, satf_error *err);
/* Frees frames, features, hair and the neighbour cache. */
void satf_shell_geom_destroy(satf_shell_geom *g);
/* Sets g->hair from dirs (satf_sector_hair_directions: 3 floats a sector,
 * zero where no strand passes): each direction less its part along the
 * sector's outward normal N, normalised; N x T where dirs is zero or runs
 * along N. The shells draw fibres lying in their layers: a strand's
 * course across the layers, which the records cannot show, is left out
 * (docs/shading.md, "Where the strands run"). Bumps g->serial. */
satf_status satf_shell_geom_set_hair(satf_shell_geom *g, const float *dirs,
                                     satf_error *err);
/* Sector q's fibre direction: g->hair's, or N x T of its frame. */
void maps_sector_hair(const satf_shell_geom *g, size_t q, float hair[3]);
size_t satf_shell_sector_count(const satf_shell_params *shell);

typedef struct satf_maps satf_maps;

/* The widest database records (samples across a sector) the maps take:
 * each look-up keeps records on the stack. The database itself allows
 * wider ones (db/params.c), which the renderer refuses. */
#define MAPS_MAX_WIDTH 512

typedef struct satf_map_options {
  float k_threshold; /* eq. 6 uniformity threshold (normalised units) */
  int k_nearest;     /* database samples blended per look-up */
  /* 1 (default): a looked-up record keeps its structure across the HSV but
   * takes the level (reflectance per unit coverage) its samples have
   * seen and lit from outside on average, whatever the sector's own
   * azimuths; 0: the record's own level (maps.c: lay_row). The renderer
   * gives it to clusters whose density is their strands' (imported hair,
   * overlapping clusters carved out of one mass of hair); a cluster of
   * procedural density is a wisp of its own, which the records' own
   * level shades round, lit on the light's side (samples/cluster_6a). */
  int orientation_free;
  /* the physical mode: the cluster's fibres cross its trajectory at this
   * angle (radians; from satf_scene_density.curl), M_p averaged over the
   * cone */
  float tilt;
} satf_map_options;

satf_map_options satf_map_options_default(void);

/* Builds the per-database tables (record-to-phase resampling). */
satf_status satf_maps_create(const satf_db *db, satf_maps **out,
                             satf_error *err);
void satf_maps_destroy(satf_maps *maps);
int satf_maps_width(const satf_maps *maps);

/* Finds and keeps g->neighbors for g->features (replacing any earlier
 * cache, which the caller may still share: see satf_neighbor_cache_free). */
satf_status satf_maps_prepare(const satf_maps *maps, satf_shell_geom *g,
                              const satf_map_options *opt, satf_error *err);
void satf_neighbor_cache_free(satf_neighbor_cache *cache);

/* Azimuths of every sector of a prototype for a viewer at eye and a light
 * (xyz, w = 0: direction towards the light, w = 1: position), both in the
 * prototype's local frame. angles: 2 floats per sector (theta_v, theta_l). */
void satf_maps_angles(const satf_shell_geom *g, const float eye[3],
                      const float light[4], float *angles);

/* Fills layer k of a cluster's texture (see top of file) from the sector
 * angles; returns the number of database look-ups made. */
int satf_maps_build_layer(const satf_maps *maps, const satf_shell_geom *g,
                          const float *angles, const satf_map_options *opt,
                          int k, float *texels);

/* The same for the HSVs of layer k whose sectors' azimuths differ from
 * `prev` (the angles of their last look-up, NaN where none; NULL: every
 * HSV), leaving the other HSVs' texels as they are: what a full build
 * would give again. The s-map sums are not touched. */
int satf_maps_update_layer(const satf_maps *maps, const satf_shell_geom *g,
                           const float *angles, const float *prev,
                           const satf_map_options *opt, int k, float *texels);

/* Eq. 12 sums: channel 2 of layer k = sum of the alpha of layers m > k. */
void satf_maps_shadow_sums(const satf_shell_geom *g, int width, float *texels);

/* How visible the HSV boundaries are in a layer's maps: sums of the absolute
 * differences of reflectance (channel 0, where both texels have alpha above
 * 0.05: below it reflectance is re / alpha of almost nothing) and of alpha
 * (channel 1) between neighbouring columns, split into pairs across an HSV
 * boundary along the phase (column w - 1 of HSV j and column 0 of HSV
 * j + 1, the same phase step apart as neighbours inside an HSV) and pairs
 * inside an HSV. Along t, the pairs of rows 2i + 1 and 2i + 2 (both at
 * t_{i+1}, one per HSV) are summed apart: 0 when neighbouring HSVs agree
 * there. edge / inner near 1: no visible seam. The records' own profile
 * across an HSV (alpha ramps up along the phase where the view is oblique:
 * a ray entering near the sector's side leaves it soon) shows as a jump at
 * every boundary whatever the look-up; the "hsv" sums cancel it, comparing
 * column x of HSV j with column x of HSV j + 1: how much the looked-up
 * records change from one HSV to the next (a patchwork with k = 1). */
typedef struct satf_maps_seams {
  double re_edge, re_inner, re_t, re_hsv; /* sums of |difference| */
  double al_edge, al_inner, al_t, al_hsv;
  long n_re_edge, n_re_inner, n_re_t, n_re_hsv; /* pairs summed */
  long n_al_edge, n_al_inner, n_al_t, n_al_hsv;
} satf_maps_seams;

/* Adds layer `texels` (one layer of the layout above) to *acc. */
void satf_maps_seams_add(const satf_shell_geom *g, int width,
                         const float *texels, satf_maps_seams *acc);
/* Mean jump across HSV boundaries over the mean step inside an HSV, for
 * reflectance and alpha (0 where nothing was summed). */
void satf_maps_seams_ratio(const satf_maps_seams *acc, double *re,
                           double *alpha);
/* What a record's re / alpha is multiplied by in the maps: 1 / the
 * reflectance per unit coverage of hair that nothing shadows, one for the
 * whole database (maps.c: reflectance_scale). */
float maps_reflectance_scale(const satf_maps *maps);

/* For the physical mode's maps (maps_fiber.c), which lay records the same
 * way: the index of sector (i, k, j); the database; the cached neighbours
 * of sector q when the cache was made for k nearest (else NULL); the
 * record sample left of each column and the weight of the next, for a
 * record seen from view azimuth `view`. */
size_t maps_sector_index(const satf_shell_params *shell, int i, int k, int j);
const satf_db *maps_db(const satf_maps *maps);
const satf_db_neighbors *maps_sector_neighbors(const satf_shell_geom *g,
                                               size_t q, int k);
void maps_columns(const satf_maps *maps, float view, const uint16_t **index,
                  const float **frac);
/* The cached neighbours of HSV q (its averaged features) under the same
 * condition as maps_sector_neighbors. */
const satf_db_neighbors *maps_hsv_neighbors(const satf_shell_geom *g, size_t q,
                                            int k);
/* The whole resampling table behind maps_columns: MAPS_AZIMUTH_BINS rows
 * of width columns, view azimuth bin b = 2 pi b / MAPS_AZIMUTH_BINS at
 * row b; and per database sample the level lay_row takes (sample_re). */
#define MAPS_AZIMUTH_BINS 1024
void maps_column_table(const satf_maps *maps, const uint16_t **index,
                       const float **frac);
const float *maps_sample_levels(const satf_maps *maps);
/* Azimuth of d in the plane of the sector whose frame (satf_shell_geom's 9
 * floats) is `frame`: from its outward normal N towards its phase
 * direction T, in [0, 2 pi); what satf_maps_angles computes. */
float maps_azimuth(const float *frame, const float d[3]);
/* A record's value between samples i and i + 1 at weight f (a column). */
static inline float maps_sample(const float *v, int i, float f) {
  return v[i] + f * (v[i + 1] - v[i]);
}

/* Texels in one layer: su * width * 2 * st, maps_hsv_texels(width) an
 * HSV (its columns, in the rows of its two boundary sectors). */
size_t satf_maps_layer_texels(const satf_shell_geom *g, int width);
size_t maps_hsv_texels(int width);

#endif
