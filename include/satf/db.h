/* db.h - the HRIR database (SATF paper sec. 4-5) and the SATF look-up
 * (eq. 4): records of reflectance + alpha, indexed by the density features
 * of the sector they came from and by the view and light azimuths.
 *
 * The file is an OpenEXR image (see docs in README, "HRIR-DB format"): any
 * EXR viewer shows the database as a picture. */
#ifndef SATF_DB_H
#define SATF_DB_H

#include <stdint.h>

#include "satf/sector.h"
#include "satf/trace.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SATF_DB_FORMAT_VERSION 1
#define SATF_FEATURES 3 /* rho_st, rho_s, rho_t */

/* SATF sec. 5.2: rho_feature = (rho_st, rho_s, rho_t). rho_st is the mean
 * density over the grid. Read literally, the "averages of the histograms
 * projected on s and t" both equal rho_st, so rho_s and rho_t are the
 * density-weighted mean positions (centroids) along s and along t, in
 * [0, 1]; an empty sector has centroids 0.5. */
void satf_density_features(const float *density, int ns, int nt,
                           float out[SATF_FEATURES]);

/* Everything a build depends on; stored in the file. */
typedef struct satf_build_params {
  uint64_t seed;
  int samples; /* number of random sectors */
  int n_view;  /* view azimuths over the full circle */
  int n_light; /* light azimuths over the full circle */
  int grid;    /* density grid nodes along s and t */
  satf_sector_shape shape;
  satf_trace_params trace;
} satf_build_params;

satf_build_params satf_build_params_default(void);
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

/* Writable storage for builders: the features[3] of sample i, and record
 * (sample, iv, il). In memory a record's reflectance and alpha are
 * adjacent, and records of neighbouring view azimuths too, so a look-up
 * reads two contiguous runs. */
float *satf_db_sample_features(satf_db *db, int i);
void satf_db_record_mut(satf_db *db, int sample, int iv, int il, float **re,
                        float **alpha);

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

/* File I/O. Writing goes through a temporary file renamed into place. */
satf_status satf_db_write(const satf_db *db, const char *path, satf_error *err);
satf_status satf_db_read(const char *path, satf_db **out, satf_error *err);
/* Writes the records as an RGBA image (R = G = B = reflectance, A = alpha)
 * in the file's pixel layout, for viewers that do not show Y/A images. */
satf_status satf_db_write_atlas(const satf_db *db, const char *path,
                                satf_error *err);
/* satf_db_read checks the integrity hash and fails with SATF_ERR_CORRUPT on
 * a mismatch; this is the hash it computes: 64-bit FNV-1a over the build
 * parameters, the features and every stored value. */
uint64_t satf_db_payload_hash(const satf_db *db);

#ifdef __cplusplus
}
#endif
#endif
