/* build.c - parallel HRIR database construction (SATF sec. 5). */
#include "satf/offline.h"

#include <stdlib.h>
#include <string.h>

#include "satf/common.h"

satf_status satf_build_sector(const satf_build_params *p, uint64_t seed,
                              uint64_t index, satf_sector **out,
                              satf_error *err) {
  satf_sector_recipe recipe;
  satf_sector_ranges ranges = satf_sector_ranges_default(p->kind);
  satf_sector_recipe_draw(seed, index, &ranges, &recipe);
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
  int first;       /* sample of item 0 */
  float *rec;      /* the range's values, satf_db_sample_floats per sample */
  float *features; /* the range's features */
  worker_buf *bufs;
} build_ctx;

/* Fibre records (offline/trace_fiber.c) of item i into the range's
 * values; sec is destroyed. b->re holds every channel of every record. */
static int build_one_fiber(build_ctx *c, size_t i, satf_sector *sec,
                           worker_buf *b) {
  const satf_build_params *p = c->p;
  satf_status st = satf_trace_fiber_all(sec, &p->fiber, p->trace.width,
                                        p->n_view, p->n_light, p->seed,
                                        (uint64_t)c->first + i, b->re, &b->err);
  satf_sector_destroy(sec);
  if (st != SATF_OK)
    return 1;
  size_t rec = (size_t)satf_build_params_channels(p) * (size_t)p->trace.width;
  size_t per = satf_db_sample_floats(p);
  float *sample = c->rec + i * per;
  for (int iv = 0; iv < p->n_view; iv++)
    for (int il = 0; il < p->n_light; il++)
      /* view-major from the tracer, light-major in the database */
      memcpy(sample + ((size_t)il * (size_t)p->n_view + (size_t)iv) * rec,
             b->re + ((size_t)iv * (size_t)p->n_light + (size_t)il) * rec,
             rec * sizeof(float));
  satf_db_round_half(sample, per);
  return 0;
}

static int build_one(void *vctx, size_t i, int thread) {
  build_ctx *c = vctx;
  const satf_build_params *p = c->p;
  worker_buf *b = &c->bufs[thread];
  satf_sector *sec = NULL;
  if (satf_build_sector(p, p->seed, (uint64_t)c->first + i, &sec, &b->err) !=
      SATF_OK)
    return 1;
  satf_density_features(sec->density, sec->ns, sec->nt,
                        c->features + i * SATF_FEATURES);
  if (p->kind == SATF_RECORD_FIBER)
    return build_one_fiber(c, i, sec, b);
  satf_status st = satf_trace_all(sec, &p->trace, p->n_view, p->n_light, b->re,
                                  b->alpha, &b->err);
  satf_sector_destroy(sec);
  if (st != SATF_OK)
    return 1;
  size_t w = (size_t)p->trace.width, per = satf_db_sample_floats(p);
  size_t nc = (size_t)satf_build_params_channels(p);
  float *sample = c->rec + i * per;
  for (int iv = 0; iv < p->n_view; iv++)
    for (int il = 0; il < p->n_light; il++) {
      size_t src = ((size_t)iv * (size_t)p->n_light + (size_t)il) * w;
      /* the database's record layout (satf_db_record_channels_mut):
       * light-major, channel-major within a record */
      float *re =
          sample + ((size_t)il * (size_t)p->n_view + (size_t)iv) * nc * w;
      memcpy(re, b->re + src, w * sizeof(float));
      memcpy(re + w, b->alpha + src, w * sizeof(float));
    }
  satf_db_round_half(sample, per);
  return 0;
}

satf_status satf_build_range(const satf_build_params *p, int first, int count,
                             int threads, satf_build_progress progress,
                             void *progress_ctx, float *rec, float *features,
                             satf_error *err) {
  satf_status st = satf_build_params_check(p, err);
  if (st != SATF_OK)
    return st;
  if (first < 0 || count < 0 || count > p->samples - first)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "samples %d..%d are outside the build's %d", first,
                          first + count - 1, p->samples);
  if (count == 0)
    return SATF_OK;
  if (threads <= 0)
    threads = satf_cpu_count();
  if (threads > count)
    threads = count;
  size_t per = (size_t)p->n_view * (size_t)p->n_light * (size_t)p->trace.width;
  build_ctx c = {p, first, rec, features,
                 calloc((size_t)threads, sizeof(worker_buf))};
  int ok = c.bufs != NULL;
  for (int t = 0; ok && t < threads; t++) {
    /* fibre records: every channel in re (build_one_fiber) */
    c.bufs[t].re = malloc(per * sizeof(float) *
                          (p->kind == SATF_RECORD_FIBER
                               ? (size_t)satf_build_params_channels(p)
                               : 1));
    c.bufs[t].alpha = malloc(per * sizeof(float));
    ok = c.bufs[t].re && c.bufs[t].alpha;
  }
  if (!ok) {
    st = satf_error_set(err, SATF_ERR_NOMEM, "cannot allocate build buffers");
  } else if (satf_parallel_for((size_t)count, threads, build_one, &c, progress,
                               progress_ctx) != 0) {
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
  return st;
}

satf_status satf_build(const satf_build_params *p, int threads,
                       satf_build_progress progress, void *progress_ctx,
                       satf_db **out, satf_error *err) {
  *out = NULL;
  satf_db *db = NULL;
  satf_status st = satf_db_create(p, &db, err);
  if (st == SATF_OK)
    st = satf_build_range(p, 0, p->samples, threads, progress, progress_ctx,
                          satf_db_samples_mut(db, 0),
                          satf_db_sample_features(db, 0), err);
  if (st == SATF_OK)
    st = satf_db_finalize(db, err);
  if (st != SATF_OK) {
    satf_db_destroy(db);
    return st;
  }
  *out = db;
  return SATF_OK;
}

satf_status satf_build_part(const satf_build_params *p, int index, int parts,
                            int threads, satf_build_progress progress,
                            void *progress_ctx, satf_db_part **out,
                            satf_error *err) {
  satf_db_part *part = NULL;
  satf_status st = satf_db_part_create(p, index, parts, &part, err);
  if (st == SATF_OK)
    st = satf_build_range(p, part->first, part->count, threads, progress,
                          progress_ctx, part->rec, part->features, err);
  if (st != SATF_OK) {
    satf_db_part_destroy(part);
    part = NULL;
  }
  *out = part;
  return st;
}
