/* part.c - parts of one database build (satf/db.h "Parts"): their sample
 * ranges, memory and hash (read and written by part_file.c, merged by
 * part_merge.c). */
#include <Imath/half.h>
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

#include "hrir_db_internal.h"

size_t satf_db_sample_floats(const satf_build_params *p) {
  return (size_t)satf_build_params_channels(p) * (size_t)p->n_view *
         (size_t)p->n_light * (size_t)p->trace.width;
}

void satf_db_part_range(int samples, int index, int parts, int *first,
                        int *count) {
  long long a = (long long)samples * index / parts;
  long long b = (long long)samples * (index + 1) / parts;
  *first = (int)a;
  *count = (int)(b - a);
}

void satf_db_round_half(float *values, size_t n) {
  for (size_t i = 0; i < n; i++)
    values[i] = imath_half_to_float(imath_float_to_half(values[i]));
}

float *satf_db_samples_mut(satf_db *db, int first) {
  satf_db_halfs_drop(db);
  return db->rec + (size_t)first * satf_db_sample_floats(&db->p);
}

satf_status satf_db_part_create(const satf_build_params *p, int index,
                                int parts, satf_db_part **out,
                                satf_error *err) {
  *out = NULL;
  satf_status st = satf_build_params_check(p, err);
  if (st != SATF_OK)
    return st;
  if (parts < 1 || parts > p->samples || index < 0 || index >= parts)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "part %d of %d: need 0 <= part < parts <= samples "
                          "(%d)",
                          index, parts, p->samples);
  satf_db_part *part = calloc(1, sizeof *part);
  if (!part)
    return satf_error_set(err, SATF_ERR_NOMEM, "cannot allocate a part");
  part->p = *p;
  part->index = index;
  part->parts = parts;
  satf_db_part_range(p->samples, index, parts, &part->first, &part->count);
  part->rec =
      calloc((size_t)part->count * satf_db_sample_floats(p), sizeof(float));
  part->features = calloc((size_t)part->count * SATF_FEATURES, sizeof(float));
  if (!part->rec || !part->features) {
    int count = part->count;
    satf_db_part_destroy(part);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot allocate part %d of %d (%d samples)", index,
                          parts, count);
  }
  *out = part;
  return SATF_OK;
}

void satf_db_part_destroy(satf_db_part *part) {
  if (part) {
    free(part->rec);
    free(part->features);
    free(part);
  }
}

uint64_t satf_db_part_hash(const satf_db_part *part) {
  int32_t place[4] = {part->index, part->parts, part->first, part->count};
  uint64_t h = satf_db_params_hash(&part->p);
  h = satf_db_fnv(h, place, sizeof place);
  h = satf_db_fnv(h, part->features,
                  (size_t)part->count * SATF_FEATURES * sizeof(float));
  return satf_db_fnv(h, part->rec,
                     (size_t)part->count * satf_db_sample_floats(&part->p) *
                         sizeof(float));
}
