/* db.h - the HRIR database (SATF paper sec. 4-5) and the SATF look-up
 * (eq. 4): records of reflectance + alpha, indexed by the density features
 * of the sector they came from and by the view and light azimuths.
 *
 * The file is an OpenEXR image (docs/formats.md, "HRIR database"): any
 * EXR viewer shows the database as a picture. */
#ifndef SATF_DB_H
#define SATF_DB_H

#include <stdint.h>

#include "satf/satf.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The newest format this satf reads and writes: 2 (fibre records);
 * Phong databases are still written, and read, as version 1. */
#define SATF_DB_FORMAT_VERSION 2
#define SATF_FEATURES 3 /* rho_st, rho_s, rho_t */

/* The record contract: what a database records and what a renderer must
 * match to read it (db/params.c). Generalized sectors (SATF paper
 * sec. 3.2-3.3): a 2-D annular region of a cluster's cross-section (a track
 * between two radii, a span of phase) carrying a hair density field on a grid
 * in its (s, t) coordinates.
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

/* Extent [lo, hi] of the sector shape projected on the unit axis e. */
void satf_sector_extent(const satf_sector_shape *shape, const float e[2],
                        float *lo, float *hi);

/* Planar ray tracing of a sector into HRIR records (SATF sec. 5.1, eq. 5):
 * the geometry of a record.
 *
 * Angles are azimuths in the sector's plane, measured from the sector's
 * outward direction (+x) towards increasing phase (+y): theta_v points from
 * the sector to the viewer, theta_l from the sector to the light.
 *
 * Record layout. Rays are parallel, travelling along -(cos theta_v,
 * sin theta_v). Sample j of an n-sample record is the ray through the
 * projected position p_j = pmin + (j + 0.5) (pmax - pmin) / n along the
 * screen axis e = (-sin theta_v, cos theta_v), where [pmin, pmax] is the
 * sector's extent projected on e (satf_trace_extent). A renderer lays a
 * record across an HSV by projecting the fragment's sector-plane position
 * onto e the same way. */

typedef struct satf_trace_params {
  int width;          /* samples per HRIR (rays across the projected width) */
  float extinction;   /* opacity per unit density per unit length */
  float ambient;      /* Phong k_a */
  float diffuse;      /* Phong k_d */
  float specular;     /* Phong k_s */
  float shininess;    /* Phong exponent */
  float epsilon;      /* stop when accumulated alpha > 1 - epsilon */
  int self_shadow;    /* attenuate light by the density towards it */
  float smooth_ratio; /* Gaussian smoothing width / strand width (1.5) */
} satf_trace_params;

satf_trace_params satf_trace_params_default(void);
satf_status satf_trace_params_check(const satf_trace_params *p,
                                    satf_error *err);

/* Extent [pmin, pmax] of the sector shape projected on the screen axis. */
void satf_trace_extent(const satf_sector_shape *shape, float theta_v,
                       float *pmin, float *pmax);

/* SATF sec. 5.2: rho_feature = (rho_st, rho_s, rho_t). rho_st is the mean
 * density over the grid. Read literally, the "averages of the histograms
 * projected on s and t" both equal rho_st, so rho_s and rho_t are the
 * density-weighted mean positions (centroids) along s and along t, in
 * [0, 1]; an empty sector has centroids 0.5. */
void satf_density_features(const float *density, int ns, int nt,
                           float out[SATF_FEATURES]);

/* ---- Record kinds (format version 2) ----
 * A database holds records of one kind. Phong records (format version 1,
 * the paper's planar ray tracing) hold reflectance and alpha. Fibre records
 * (format version 2) come from 2-D Monte Carlo path tracing of the
 * sector's strands as circular fibres with the d'Eon/Chiang azimuthal
 * scattering (papers 003 and satf/fiber.h) in the fibres' normal plane:
 * theta_i = theta_o = 0, so a record holds the lateral response N_p A_p only
 * and the renderer multiplies the longitudinal M_p in.
 *
 * Fibre record channels (per record sample, each the mean over the
 * sample's sub-rays, misses counting 0, i.e. premultiplied by coverage):
 * radiance per unit irradiance of the light and per unit M_p, so that a
 * renderer computes
 *   L = E (M_R R + M_TT TT(sigma) + M_TRT TRT(sigma) + M_MS MS(sigma)).
 * R is single scattering by lobe p = 0 (absorption-free); TT[k] lobe p = 1
 * and TRT[k] lobes p >= 2 (pbrt's remainder, azimuthally uniform) of single
 * scattering, MS[k] every path of two or more fibre interactions, each at
 * absorption level k (sigma_a per unit fibre radius, satf_db_absorption_
 * levels); between levels a renderer interpolates log-linearly in sigma.
 * The radial roughness beta_n and eta are baked into the records. */
typedef enum satf_record_kind {
  SATF_RECORD_PHONG = 0, /* reflectance + alpha, format version 1 */
  SATF_RECORD_FIBER = 1  /* alpha + lobes x absorption levels, version 2 */
} satf_record_kind;

#define SATF_DB_LEVELS_MAX 8

/* Channels of a record, channel-major (channel c of a record's samples at
 * c * width). Both kinds: 0 reflectance, 1 alpha; for fibre records the
 * reflectance is R + TT[0] + TRT[0] + MS[0] (the total at the first,
 * lowest absorption level), so callers of satf_db_record and satf_db_lookup
 * keep working. Then, for fibre records with `levels` absorption levels: */
#define SATF_DB_CH_REFLECTANCE 0
#define SATF_DB_CH_ALPHA 1
#define SATF_DB_CH_R 2
#define SATF_DB_CH_TT(k) (3 + (k))
#define SATF_DB_CH_TRT(k, levels) (3 + (levels) + (k))
#define SATF_DB_CH_MS(k, levels) (3 + 2 * (levels) + (k))
#define SATF_DB_FIBER_CHANNELS(levels) (3 + 3 * (levels))

/* The fibre tracer's parameters (offline/trace_fiber.c). */
typedef struct satf_fiber_trace_params {
  float eta;    /* index of refraction (1.55) */
  float beta_n; /* radial (azimuthal) roughness, Chiang 2016 (0.3) */
  int levels;   /* absorption levels K, 1..SATF_DB_LEVELS_MAX */
  float sigma_a[SATF_DB_LEVELS_MAX]; /* per unit fibre radius, ascending */
  int sub_rays;                      /* eye rays per record sample */
  int max_bounces;                   /* fibre interactions followed per path */
} satf_fiber_trace_params;

satf_fiber_trace_params satf_fiber_trace_params_default(void);
satf_status satf_fiber_trace_params_check(const satf_fiber_trace_params *p,
                                          satf_error *err);
/* The fewest light azimuths whose grid resolves N_p of radial roughness
 * beta_n: next-event estimation sums the lobes over the grid, and a grid
 * coarser than the lobes loses or gains energy (over 1e-3). 32 for the
 * default 0.3. */
int satf_fiber_trace_min_lights(float beta_n);
const char *satf_record_kind_name(satf_record_kind kind);
/* "phong" or "fiber"; returns -1 for anything else. */
int satf_record_kind_parse(const char *name, satf_record_kind *kind);

/* Everything a build depends on; stored in the file. */
typedef struct satf_build_params {
  uint64_t seed;
  int samples; /* number of random sectors */
  int n_view;  /* view azimuths over the full circle */
  int n_light; /* light azimuths over the full circle */
  int grid;    /* density grid nodes along s and t */
  satf_sector_shape shape;
  satf_trace_params trace;       /* width for both kinds; the rest Phong only */
  satf_record_kind kind;         /* SATF_RECORD_PHONG unless asked */
  satf_fiber_trace_params fiber; /* fibre records only */
} satf_build_params;

satf_build_params satf_build_params_default(void);
/* The default fibre database (satf-build --kind fiber): docs/shading.md. */
satf_build_params satf_build_params_default_fiber(void);
/* Channels of a record of a build: 2 for Phong, SATF_DB_FIBER_CHANNELS. */
int satf_build_params_channels(const satf_build_params *p);
/* The format version a build's file has: 1 for Phong, 2 for fibre. */
int satf_build_params_version(const satf_build_params *p);
satf_status satf_build_params_check(const satf_build_params *p,
                                    satf_error *err);

typedef struct satf_db satf_db;

/* Creates an empty database with room for p->samples records sets. */
satf_status satf_db_create(const satf_build_params *p, satf_db **out,
                           satf_error *err);
void satf_db_destroy(satf_db *db);

const satf_build_params *satf_db_params(const satf_db *db);
int satf_db_width(const satf_db *db);
int satf_db_samples(const satf_db *db);
/* Channels per record (SATF_DB_CH_*): 2 for a Phong database. */
int satf_db_channels(const satf_db *db);
satf_record_kind satf_db_kind(const satf_db *db);
/* The absorption levels of a fibre database (sigma_a per unit fibre
 * radius, ascending); NULL and *count = 0 for Phong. */
const float *satf_db_absorption_levels(const satf_db *db, int *count);

/* Writable storage for builders: the features[3] of sample i, and record
 * (sample, iv, il). In memory a record's reflectance and alpha are
 * adjacent, and records of neighbouring view azimuths too, so a look-up
 * reads two contiguous runs. */
float *satf_db_sample_features(satf_db *db, int i);
void satf_db_record_mut(satf_db *db, int sample, int iv, int il, float **re,
                        float **alpha);
/* Every channel of record (sample, iv, il): satf_db_channels x width
 * values, channel-major (SATF_DB_CH_*). */
float *satf_db_record_channels_mut(satf_db *db, int sample, int iv, int il);
const float *satf_db_record_channels(const satf_db *db, int sample, int iv,
                                     int il);

/* Rounds every stored value to what the file keeps (half floats) and builds
 * the look-up index. Call after filling, before look-ups or writing. */
satf_status satf_db_finalize(satf_db *db, satf_error *err);

/* Read-only record (sample, iv, il): width values each. */
void satf_db_record(const satf_db *db, int sample, int iv, int il,
                    const float **re, const float **alpha);
/* Feature vector of a sample, and the per-feature range over all samples. */
const float *satf_db_features(const satf_db *db, int sample);
void satf_db_feature_range(const satf_db *db, float lo[SATF_FEATURES],
                           float hi[SATF_FEATURES]);

/* The k samples nearest to `feature` in range-normalised feature space,
 * nearest first; writes up to k indices and squared distances, returns how
 * many were found. */
int satf_db_nearest(const satf_db *db, const float feature[SATF_FEATURES],
                    int k, int *index, float *dist2);

/* SATF eq. 4: HRIR(rho_feature, theta_v, theta_l). Blends the k nearest
 * samples (k = 1: nearest only) by inverse distance, each bilinearly
 * interpolated between the four stored azimuth pairs around (theta_v,
 * theta_l), periodically. Writes width values to re and alpha. */
void satf_db_lookup(const satf_db *db, const float feature[SATF_FEATURES],
                    float theta_v, float theta_l, int k, float *re,
                    float *alpha);

/* The look-up in two steps, for callers whose features stay while the
 * angles change (the renderer's sectors): the k nearest samples and their
 * normalised inverse-distance weights, then the periodic bilinear blend at
 * any azimuths. Together equal to satf_db_lookup, value for value. */
#define SATF_DB_KMAX 16
typedef struct satf_db_neighbors {
  int count;
  int index[SATF_DB_KMAX];
  float weight[SATF_DB_KMAX];
} satf_db_neighbors;

void satf_db_neighbors_find(const satf_db *db,
                            const float feature[SATF_FEATURES], int k,
                            satf_db_neighbors *out);
void satf_db_lookup_neighbors(const satf_db *db, const satf_db_neighbors *nb,
                              float theta_v, float theta_l, float *re,
                              float *alpha);
/* The same blend over every channel: out holds satf_db_channels x width
 * values, channel-major (channel c at c * width, SATF_DB_CH_*). */
void satf_db_lookup_neighbors_channels(const satf_db *db,
                                       const satf_db_neighbors *nb,
                                       float theta_v, float theta_l,
                                       float *out);
/* The blend of channels [ch0, ch0 + nch) only (0 <= ch0, ch0 + nch <=
 * satf_db_channels): out holds nch x width values, channel ch0 + c at
 * c * width, each equal bit for bit to that channel of the full look-up.
 * A caller that never reads some channels (a fibre renderer, reflectance)
 * skips their blending. */
void satf_db_lookup_neighbors_range(const satf_db *db,
                                    const satf_db_neighbors *nb, float theta_v,
                                    float theta_l, int ch0, int nch,
                                    float *out);
/* Asks the processor to fetch the records that the same look-up will read,
 * for a caller to issue one look-up ahead: the records of a look-up are
 * scattered over the database (tens of MB), so each look-up otherwise
 * waits for memory. Changes no value. */
void satf_db_prefetch(const satf_db *db, const satf_db_neighbors *nb,
                      float theta_v, float theta_l, int ch0, int nch);
/* The two steps' second split again, for a caller that prefetches a
 * look-up and then makes it: the stored azimuth pairs around (theta_v,
 * theta_l) and their bilinear weights, found once for both (corners_of,
 * which finds them, took 5% of the CPU samples of hair_7c's physical
 * frames, perf, two thirds of it for the key light's prefetch and look-up).
 * satf_db_lookup_cell_range and satf_db_prefetch_cell at the cell of
 * (theta_v, theta_l) equal satf_db_lookup_neighbors_range and
 * satf_db_prefetch there, value for value. */
typedef struct satf_db_cell {
  int v[2], l[2]; /* view and light grid indices */
  float bw[4];    /* weight of (v[k & 1], l[k >> 1]) */
} satf_db_cell;
void satf_db_cell_find(const satf_db *db, float theta_v, float theta_l,
                       satf_db_cell *out);
void satf_db_lookup_cell_range(const satf_db *db, const satf_db_neighbors *nb,
                               const satf_db_cell *cell, int ch0, int nch,
                               float *out);
void satf_db_prefetch_cell(const satf_db *db, const satf_db_neighbors *nb,
                           const satf_db_cell *cell, int ch0, int nch);
/* Records up to this width take satf_db_lookup_neighbors' one-pass blend
 * (wider ones blend a channel at a time, the same values). */
#define SATF_DB_LOOKUP_MAX_WIDTH 512

/* relevel.c - a fibre database at other absorption levels. The value at
 * sigma of a lobe stored at `count` ascending levels, interpolated as the
 * record contract asks (log-linear; past the last level the last step's
 * fall continues). */
float satf_db_level_value(const float *levels, const float *values, int count,
                          float sigma);
/* A copy of fibre database db whose absorbing lobes are given at the n
 * strictly ascending levels sigma (e.g. a hair's RGB sigma_a, sorted), on
 * `threads` threads (0: all cores): a renderer shading one colour blends
 * 3 + 3 n channels a look-up and interpolates nothing per frame. */
satf_status satf_db_relevel(const satf_db *db, const float *sigma, int n,
                            int threads, satf_db **out, satf_error *err);

/* File I/O. Writing goes through a temporary file renamed into place, its
 * chunks compressed on every core (satf_db_write_threads: on `threads`,
 * 0: every core; the bytes are the same on any count). */
satf_status satf_db_write(const satf_db *db, const char *path, satf_error *err);
satf_status satf_db_write_threads(const satf_db *db, const char *path,
                                  int threads, satf_error *err);
satf_status satf_db_read(const char *path, satf_db **out, satf_error *err);
/* Writes the records as an RGBA image (R = G = B = reflectance, A = alpha)
 * in the file's pixel layout, for viewers that do not show Y/A images. */
satf_status satf_db_write_atlas(const satf_db *db, const char *path,
                                satf_error *err);
/* satf_db_read checks the integrity hash and fails with SATF_ERR_CORRUPT on
 * a mismatch; this is the hash it computes: 64-bit FNV-1a over the build
 * parameters, the features and every stored value. */
uint64_t satf_db_payload_hash(const satf_db *db);

/* ---- Parts: one build made in pieces (db/part.c, db/part_file.c) ----
 * Part I of N holds samples [first, first + count) of a build, first =
 * floor(samples * I / N). Sample i depends only on (seed, i), so parts built
 * by separate processes (MPI ranks, farm-queue shards) assemble into the
 * bytes of a one-process build. A part's values are laid out as a
 * database's samples (satf_db_samples_mut) and rounded to half floats, as
 * the file keeps them.
 *
 * The shard file is an OpenEXR image like the database's (same pixel
 * layout, count samples tall) whose header names it a shard
 * (satf:format "satf-hrirdb-shard"), holds the WHOLE build's parameters
 * and seed, satf:shardIndex, satf:shardCount, satf:first, satf:count, the
 * part's features and its own integrity hash (satf_db_part_hash). */
typedef struct satf_db_part {
  satf_build_params p; /* the whole build's parameters */
  int index, parts;    /* part I of N, 0 <= I < N */
  int first, count;    /* its samples */
  float *rec;          /* count * satf_db_sample_floats(&p) values, owned */
  float *features;     /* count * SATF_FEATURES values, owned */
} satf_db_part;

/* Values (reflectance and alpha) stored per sample. */
size_t satf_db_sample_floats(const satf_build_params *p);
/* The samples of part I of N of a build of `samples` samples. */
void satf_db_part_range(int samples, int index, int parts, int *first,
                        int *count);
/* Rounds n values to what the file keeps (half floats). */
void satf_db_round_half(float *values, size_t n);
/* Writable values of samples first.. of a database, contiguous, in the part
 * layout (satf_db_sample_floats each). */
float *satf_db_samples_mut(satf_db *db, int first);

/* A zero-filled part I of N (1 <= N <= p->samples). */
satf_status satf_db_part_create(const satf_build_params *p, int index,
                                int parts, satf_db_part **out, satf_error *err);
void satf_db_part_destroy(satf_db_part *part);
/* 64-bit FNV-1a over the parameters, the part's place, features and
 * values (the shard file's satf:hash). */
uint64_t satf_db_part_hash(const satf_db_part *part);
/* Rounds the part's values to half floats (what the file keeps) and
 * writes the shard file through a temporary file renamed into place. */
satf_status satf_db_part_write(satf_db_part *part, const char *path,
                               satf_error *err);
/* Reads a shard file and checks its header and integrity hash. */
satf_status satf_db_part_read(const char *path, satf_db_part **out,
                              satf_error *err);
/* Reads n shard files, checks that they are parts of one build (same
 * parameters and seed, same N) covering every part exactly once, and
 * assembles the finalized database: the one-process build's values. Errors
 * name the file at fault. */
satf_status satf_db_merge(const char *const *paths, int n, satf_db **out,
                          satf_error *err);

/* atlas.c - the image size of the database file and of its atlas: one row
 * per sample and light azimuth, one record of width values per view
 * azimuth. */
void satf_db_atlas_size(const satf_db *db, int *width, int *height);

#ifdef __cplusplus
}
#endif
#endif
