/* build.c - parallel HRIR database construction (SATF sec. 5). */
#include "satf/offline.h"

#include <stdlib.h>
#include <string.h>

#include "satf/common.h"

satf_status satf_build_sector(const satf_build_params *p, uint64_t seed,
                              uint64_t index, satf_sector **out,
                              satf_error *err) {
  satf_sector_recipe recipe;
  satf_sector_recipe_random(seed, index, &recipe);
  satf_status st = satf_sector_create(&p->shape, p->grid, p->grid,
                                      recipe.strand_sigma, out, err);
  if (st == SATF_OK)
    satf_sector_fill(*out, &recipe, seed, index);
  return st;
}

typedef struct worker_buf {
  float *re, *alpha; /* view-major records from satf_trace_all */
  satf_error err;
} worker_buf;

typedef struct build_ctx {
  const satf_build_params *p;
  satf_db *db;
  worker_buf *bufs;
} build_ctx;

static int build_one(void *vctx, size_t i, int thread) {
  build_ctx *c = vctx;
  const satf_build_params *p = c->p;
  worker_buf *b = &c->bufs[thread];
  satf_sector *sec = NULL;
  if (satf_build_sector(p, p->seed, i, &sec, &b->err) != SATF_OK)
    return 1;
  satf_density_features(sec->density, sec->ns, sec->nt,
                        satf_db_sample_features(c->db, (int)i));
  satf_status st = satf_trace_all(sec, &p->trace, p->n_view, p->n_light, b->re,
                                  b->alpha, &b->err);
  satf_sector_destroy(sec);
  if (st != SATF_OK)
    return 1;
  size_t w = (size_t)p->trace.width;
  for (int iv = 0; iv < p->n_view; iv++)
    for (int il = 0; il < p->n_light; il++) {
      size_t src = ((size_t)iv * (size_t)p->n_light + (size_t)il) * w;
      float *re, *alpha;
      satf_db_record_mut(c->db, (int)i, iv, il, &re, &alpha);
      memcpy(re, b->re + src, w * sizeof(float));
      memcpy(alpha, b->alpha + src, w * sizeof(float));
    }
  return 0;
}

satf_status satf_build(const satf_build_params *p, int threads,
                       satf_build_progress progress, void *progress_ctx,
                       satf_db **out, satf_error *err) {
  *out = NULL;
  satf_db *db = NULL;
  satf_status st = satf_db_create(p, &db, err);
  if (st != SATF_OK)
    return st;
  if (threads <= 0)
    threads = satf_cpu_count();
  if (threads > p->samples)
    threads = p->samples;
  size_t per = (size_t)p->n_view * (size_t)p->n_light * (size_t)p->trace.width;
  build_ctx c = {p, db, calloc((size_t)threads, sizeof(worker_buf))};
  int ok = c.bufs != NULL;
  for (int t = 0; ok && t < threads; t++) {
    c.bufs[t].re = malloc(per * sizeof(float));
    c.bufs[t].alpha = malloc(per * sizeof(float));
    ok = c.bufs[t].re && c.bufs[t].alpha;
  }
  if (!ok) {
    st = satf_error_set(err, SATF_ERR_NOMEM, "cannot allocate build buffers");
  } else if (satf_parallel_for((size_t)p->samples, threads, build_one, &c,
                               progress, progress_ctx) != 0) {
    st = SATF_ERR_INTERNAL;
    for (int t = 0; t < threads; t++)
      if (c.bufs[t].err.status != SATF_OK) {
        st = satf_error_set(err, c.bufs[t].err.status, "%s",
                            c.bufs[t].err.message);
        break;
      }
    if (st == SATF_ERR_INTERNAL)
      satf_error_set(err, st, "database build failed");
  }
  for (int t = 0; c.bufs && t < threads; t++) {
    free(c.bufs[t].re);
    free(c.bufs[t].alpha);
  }
  free(c.bufs);
  if (st == SATF_OK)
    st = satf_db_finalize(db, err);
  if (st != SATF_OK) {
    satf_db_destroy(db);
    return st;
  }
  *out = db;
  return SATF_OK;
}
