/* hrir_db_internal.h - the database's private layout, shared by the
 * in-memory part (hrir_db.c) and the file format (hrir_db_file.c). */
#ifndef SATF_DB_HRIR_DB_INTERNAL_H
#define SATF_DB_HRIR_DB_INTERNAL_H

#include "kdtree.h"
#include "satf/db.h"

struct satf_db {
  satf_build_params p;
  float *rec;      /* samples x n_light x n_view x (width re, width alpha) */
  float *features; /* samples x SATF_FEATURES */
  float lo[SATF_FEATURES], hi[SATF_FEATURES], scale[SATF_FEATURES];
  float *norm; /* features scaled to [0, 1], for the tree */
  satf_kdtree *tree;
};

/* Wraps arrays read from a file (ownership passes, even on failure). */
satf_status satf_db_adopt(const satf_build_params *p, float *rec,
                          float *features, satf_db **out, satf_error *err);
/* Offset of record (sample, iv, il) in rec. */
size_t satf_db_record_offset(const satf_db *db, int sample, int iv, int il);
/* Builds the feature ranges and the k-d tree. */
satf_status satf_db_index(satf_db *db, satf_error *err);

#endif
