/* db_compare.h - asserts two databases hold the same parameters, features
 * and records, bit for bit. Include after <cmocka.h>. */
#ifndef SATF_TESTS_DB_COMPARE_H
#define SATF_TESTS_DB_COMPARE_H

#include "satf/db.h"

static inline void assert_same_db(const satf_db *a, const satf_db *b) {
  const satf_build_params *p = satf_db_params(a), *q = satf_db_params(b);
  assert_memory_equal(p, q, sizeof *p);
  size_t w = (size_t)p->trace.width * sizeof(float);
  for (int i = 0; i < p->samples; i++) {
    assert_memory_equal(satf_db_features(a, i), satf_db_features(b, i),
                        SATF_FEATURES * sizeof(float));
    for (int iv = 0; iv < p->n_view; iv++)
      for (int il = 0; il < p->n_light; il++) {
        const float *ra, *aa, *rb, *ab;
        satf_db_record(a, i, iv, il, &ra, &aa);
        satf_db_record(b, i, iv, il, &rb, &ab);
        assert_memory_equal(ra, rb, w);
        assert_memory_equal(aa, ab, w);
      }
  }
}

#endif
