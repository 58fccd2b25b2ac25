/* hrir_db_internal.h - the database's private layout, shared by the
 * in-memory part (hrir_db.c) and the file format (hrir_db_file.c). */
#ifndef SATF_DB_HRIR_DB_INTERNAL_H
#define SATF_DB_HRIR_DB_INTERNAL_H

#include "kdtree.h"
#include "satf/common.h"
#include "satf/db.h"

struct satf_db {
  satf_build_params p;
  float *rec;      /* samples x n_light x n_view x (width re, width alpha) */
  float *features; /* samples x SATF_FEATURES */
  float lo[SATF_FEATURES], hi[SATF_FEATURES], scale[SATF_FEATURES];
  float *norm; /* features scaled to [0, 1], for the tree */
  satf_kdtree *tree;
  /* rec as half floats, what look-ups read where the processor converts
   * them (F16C): half the bytes from memory, the same values (made by
   * satf_db_index only when every value is a half exactly; NULL
   * otherwise, and dropped by any writable access to rec) */
  uint16_t *rec16;
};

/* Frees rec16 (rec is about to change). */
void satf_db_halfs_drop(satf_db *db);

/* Wraps arrays read from a file (ownership passes, even on failure). */
satf_status satf_db_adopt(const satf_build_params *p, float *rec,
                          float *features, satf_db **out, satf_error *err);
/* Offset of record (sample, iv, il) in rec. */
size_t satf_db_record_offset(const satf_db *db, int sample, int iv, int il);
/* Builds the feature ranges and the k-d tree. */
satf_status satf_db_index(satf_db *db, satf_error *err);

/* Shared by the database file and the shard file (part_file.c). */
/* The FNV-1a of satf_db_payload_hash, continued from h over more bytes, and
 * its first step: the build parameters and seed. */
uint64_t satf_db_fnv(uint64_t h, const void *data, size_t bytes);
uint64_t satf_db_params_hash(const satf_build_params *p);
/* The file's channels of a build's records, in SATF_DB_CH_* order, and
 * the copy of `samples` samples between memory (rec, the database's
 * layout) and one image plane per channel (the file's pixel layout). */
#define SATF_DB_MAX_CHANNELS SATF_DB_FIBER_CHANNELS(SATF_DB_LEVELS_MAX)
#define SATF_DB_CHANNEL_NAME 16
void satf_db_channel_names(const satf_build_params *p,
                           char names[][SATF_DB_CHANNEL_NAME]);
void satf_db_channels_copy(const satf_build_params *p, int samples, float *rec,
                           float *const *planes, int to_planes);
/* Header attributes: satf:format, version, generator and hash; the build
 * parameters and seed; their readers, which name path in errors (`what`
 * says what a file of `format` is). */
exr_result_t satf_db_format_attrs_write(exr_context_t exr, int part,
                                        const char *format, uint64_t hash);
exr_result_t satf_db_params_attrs_write(exr_context_t exr, int part,
                                        const satf_build_params *p);
satf_status satf_db_format_attrs_read(const char *path, exr_const_context_t exr,
                                      int part, const char *format,
                                      const char *what, satf_error *err);
satf_status satf_db_params_attrs_read(const char *path, exr_const_context_t exr,
                                      int part, satf_build_params *p,
                                      satf_error *err);
satf_status satf_db_hex_attr_read(const char *path, exr_const_context_t exr,
                                  int part, const char *name, uint64_t *out,
                                  satf_error *err);
/* satf:features of `samples` samples, into a new array. */
satf_status satf_db_features_attr_read(const char *path,
                                       exr_const_context_t exr, int part,
                                       int samples, float **out,
                                       satf_error *err);

#endif
