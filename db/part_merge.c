/* part_merge.c - the merge of shard files (part_file.c) into the database
 * a one-process build writes (satf/db.h "Parts"). */
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

#include "hrir_db_internal.h"

/* Why `part` (read from path) is not of the build of `first` (from
 * first_path), or SATF_OK. */
static satf_status check_same_build(const satf_db_part *first,
                                    const char *first_path,
                                    const satf_db_part *part, const char *path,
                                    satf_error *err) {
  if (part->p.seed != first->p.seed)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: a shard of another build (seed %" PRIu64
                          ", but %s has seed %" PRIu64 ")",
                          path, part->p.seed, first_path, first->p.seed);
  if (satf_db_params_hash(&part->p) != satf_db_params_hash(&first->p))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: a shard of another build (its build parameters "
                          "differ from those of %s; compare satf-db info)",
                          path, first_path);
  if (part->parts != first->parts)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: shard %d/%d, but %s is one of %d shards", path,
                          part->index, part->parts, first_path, first->parts);
  return SATF_OK;
}

/* The first shard no file gave, as an error. */
static satf_status missing(const char *const *owner, int parts, int n,
                           satf_error *err) {
  for (int i = 0; i < parts; i++)
    if (!owner[i])
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "shard %d/%d is missing: %d file%s given, %d "
                            "shard%s needed (build it with satf-build "
                            "--shard %d/%d)",
                            i, parts, n, n == 1 ? "" : "s", parts,
                            parts == 1 ? "" : "s", i, parts);
  return SATF_OK;
}

/* The merge so far: the database, created from the first shard, whose
 * header (values freed) the others are checked against, and which file
 * gave each shard. */
typedef struct merge_state {
  satf_db *db;
  satf_db_part *first;
  const char **owner;
} merge_state;

/* Reads the shard at paths[k], checks it against the first and places its
 * values into the database. */
static satf_status merge_one(const char *const *paths, int k, merge_state *m,
                             satf_error *err) {
  satf_db_part *part = NULL;
  satf_status st = satf_db_part_read(paths[k], &part, err);
  if (st != SATF_OK)
    return st;
  if (!m->first) {
    m->owner = calloc((size_t)part->parts, sizeof *m->owner);
    st = m->owner ? satf_db_create(&part->p, &m->db, err)
                  : satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  } else {
    st = check_same_build(m->first, paths[0], part, paths[k], err);
  }
  if (st == SATF_OK && m->owner[part->index])
    st = satf_error_set(
        err, SATF_ERR_ARGUMENT, "%s: shard %d/%d again (%s is that shard too)",
        paths[k], part->index, part->parts, m->owner[part->index]);
  if (st != SATF_OK) {
    satf_db_part_destroy(part);
    return st;
  }
  m->owner[part->index] = paths[k];
  memcpy(satf_db_samples_mut(m->db, part->first), part->rec,
         (size_t)part->count * satf_db_sample_floats(&part->p) * sizeof(float));
  memcpy(satf_db_sample_features(m->db, part->first), part->features,
         (size_t)part->count * SATF_FEATURES * sizeof(float));
  if (m->first) {
    satf_db_part_destroy(part);
  } else {
    free(part->rec);
    free(part->features);
    part->rec = part->features = NULL;
    m->first = part;
  }
  return SATF_OK;
}

satf_status satf_db_merge(const char *const *paths, int n, satf_db **out,
                          satf_error *err) {
  *out = NULL;
  if (n < 1)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "no shard files to merge");
  merge_state m = {NULL, NULL, NULL};
  satf_status st = SATF_OK;
  /* one shard in memory at a time beside the database */
  for (int k = 0; k < n && st == SATF_OK; k++)
    st = merge_one(paths, k, &m, err);
  if (st == SATF_OK)
    st = missing(m.owner, m.first->parts, n, err);
  free(m.owner);
  satf_db_part_destroy(m.first);
  if (st == SATF_OK)
    st = satf_db_finalize(m.db, err);
  if (st != SATF_OK) {
    satf_db_destroy(m.db);
    return st;
  }
  *out = m.db;
  return SATF_OK;
}
