/* part_file.c - the shard file (satf/db.h "Parts"): one part of a build as
 * an OpenEXR image in the database file's pixel layout, whose header holds
 * the whole build's parameters, the part's place and its own hash. */
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

#include "hrir_db_internal.h"

#define SHARD_FORMAT "satf-hrirdb-shard"

typedef struct place_attr {
  const char *name;
  int *field;
} place_attr;

/* The part's place in the build, one table for writer and reader. */
#define PLACE_ATTRS(q)                                                         \
  {                                                                            \
    {"satf:shardIndex", &(q)->index}, {"satf:shardCount", &(q)->parts},        \
        {"satf:first", &(q)->first}, {                                         \
      "satf:count", &(q)->count                                                \
    }                                                                          \
  }

static satf_status write_attrs(void *ctx, exr_context_t exr, int part,
                               satf_error *err) {
  satf_db_part q = *(const satf_db_part *)ctx;
  place_attr place[] = PLACE_ATTRS(&q);
  exr_result_t rc = satf_db_format_attrs_write(exr, part, SHARD_FORMAT,
                                               satf_db_part_hash(&q));
  if (rc == EXR_ERR_SUCCESS)
    rc = satf_db_params_attrs_write(exr, part, &q.p);
  for (int i = 0; i < 4 && rc == EXR_ERR_SUCCESS; i++)
    rc = exr_attr_set_int(exr, part, place[i].name, *place[i].field);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_float_vector(exr, part, "satf:features",
                                   q.count * SATF_FEATURES, q.features);
  if (rc != EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_IO, "cannot set header attributes: %s",
                          exr_get_error_code_as_string(rc));
  return SATF_OK;
}

satf_status satf_db_part_write(satf_db_part *part, const char *path,
                               satf_error *err) {
  const satf_build_params *p = &part->p;
  size_t n = (size_t)part->count * satf_db_sample_floats(p);
  satf_db_round_half(part->rec, n);
  float *re = malloc(n / 2 * sizeof(float)),
        *alpha = malloc(n / 2 * sizeof(float));
  if (!re || !alpha) {
    free(re);
    free(alpha);
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  }
  satf_db_planes_copy(p, part->count, part->rec, re, alpha, 1);
  satf_exr_channel ch[2] = {{"A", alpha}, {"Y", re}};
  satf_exr_write_opts opts = {EXR_PIXEL_HALF, EXR_COMPRESSION_ZIP, write_attrs,
                              part};
  satf_status st = satf_exr_write(path, p->n_view * p->trace.width,
                                  part->count * p->n_light, ch, 2, &opts, err);
  free(re);
  free(alpha);
  return st;
}

typedef struct read_ctx {
  const char *path;
  satf_db_part q; /* the header; features owned until adopted */
  uint64_t hash;
} read_ctx;

/* The part's place must be the one satf_db_part_range gives. */
static satf_status check_place(const char *path, const satf_db_part *q,
                               satf_error *err) {
  int first, count;
  if (q->parts < 1 || q->parts > q->p.samples || q->index < 0 ||
      q->index >= q->parts)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: shard %d/%d of a %d-sample build is impossible",
                          path, q->index, q->parts, q->p.samples);
  satf_db_part_range(q->p.samples, q->index, q->parts, &first, &count);
  if (q->first != first || q->count != count)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: shard %d/%d holds samples %d..%d, but that "
                          "shard is samples %d..%d",
                          path, q->index, q->parts, q->first,
                          q->first + q->count - 1, first, first + count - 1);
  return SATF_OK;
}

static satf_status read_attrs(void *vctx, exr_const_context_t exr, int part,
                              int width, int height, satf_error *err) {
  read_ctx *rc = vctx;
  const char *path = rc->path;
  satf_db_part *q = &rc->q;
  place_attr place[] = PLACE_ATTRS(q);
  satf_status st = satf_db_format_attrs_read(path, exr, part, SHARD_FORMAT,
                                             "an satf database shard", err);
  if (st == SATF_OK)
    st = satf_db_params_attrs_read(path, exr, part, &q->p, err);
  if (st == SATF_OK)
    st = satf_db_hex_attr_read(path, exr, part, "satf:hash", &rc->hash, err);
  for (int i = 0; i < 4 && st == SATF_OK; i++)
    if (exr_attr_get_int(exr, part, place[i].name, place[i].field) !=
        EXR_ERR_SUCCESS)
      st = satf_error_set(err, SATF_ERR_CORRUPT, "%s: missing %s", path,
                          place[i].name);
  if (st == SATF_OK)
    st = check_place(path, q, err);
  if (st != SATF_OK)
    return st;
  const satf_build_params *p = &q->p;
  if ((long long)width != (long long)p->n_view * p->trace.width ||
      (long long)height != (long long)q->count * p->n_light)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: image is %dx%d but the shard's parameters say "
                          "%dx%d",
                          path, width, height, p->n_view * p->trace.width,
                          q->count * p->n_light);
  return satf_db_features_attr_read(path, exr, part, q->count, &q->features,
                                    err);
}

satf_status satf_db_part_read(const char *path, satf_db_part **out,
                              satf_error *err) {
  *out = NULL;
  read_ctx rc;
  memset(&rc, 0, sizeof rc);
  rc.path = path;
  const char *names[2] = {"A", "Y"};
  float *planes[2] = {NULL, NULL};
  int w = 0, h = 0;
  satf_status st = satf_exr_read(path, names, 2, 1LL << 31, read_attrs, &rc, &w,
                                 &h, planes, err);
  satf_db_part *q = NULL;
  if (st == SATF_OK) {
    q = calloc(1, sizeof *q);
    if (q) {
      *q = rc.q;
      rc.q.features = NULL;
      q->rec = malloc((size_t)q->count * satf_db_sample_floats(&q->p) *
                      sizeof(float));
    }
    if (!q || !q->rec)
      st = satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  }
  if (st == SATF_OK)
    satf_db_planes_copy(&q->p, q->count, q->rec, planes[1], planes[0], 0);
  free(planes[0]);
  free(planes[1]);
  free(rc.q.features);
  uint64_t actual = st == SATF_OK ? satf_db_part_hash(q) : 0;
  if (st == SATF_OK && actual != rc.hash)
    st = satf_error_set(err, SATF_ERR_CORRUPT,
                        "%s: integrity check failed (stored hash %016" PRIx64
                        ", computed %016" PRIx64 "): the shard is damaged",
                        path, rc.hash, actual);
  if (st != SATF_OK) {
    satf_db_part_destroy(q);
    return st;
  }
  *out = q;
  return SATF_OK;
}
