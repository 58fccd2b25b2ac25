/* part_file.c - the shard file (satf/db.h "Parts"): one part of a build as
 * an OpenEXR image in the database file's pixel layout, whose header holds
 * the whole build's parameters, the part's place and its own hash. */
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

#include "hrir_db_internal.h"

#define SHARD_FORMAT "satf-hrirdb-shard"

/* The part's place in the build: the attributes, and the fields of the
 * part they hold, in one order for writer and reader. */
static const char *const PLACE_NAMES[4] = {"satf:shardIndex", "satf:shardCount",
                                           "satf:first", "satf:count"};

static void place_fields(satf_db_part *q, int *field[4]) {
  field[0] = &q->index;
  field[1] = &q->parts;
  field[2] = &q->first;
  field[3] = &q->count;
}

static satf_status write_attrs(void *ctx, exr_context_t exr, int part,
                               satf_error *err) {
  satf_db_part q = *(const satf_db_part *)ctx;
  int *place[4];
  place_fields(&q, place);
  exr_result_t rc = satf_db_format_attrs_write(exr, part, SHARD_FORMAT,
                                               satf_db_part_hash(&q));
  if (rc == EXR_ERR_SUCCESS)
    rc = satf_db_params_attrs_write(exr, part, &q.p);
  for (int i = 0; i < 4 && rc == EXR_ERR_SUCCESS; i++)
    rc = exr_attr_set_int(exr, part, PLACE_NAMES[i], *place[i]);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_float_vector(exr, part, "satf:features",
                                   q.count * SATF_FEATURES, q.features);
  if (rc != EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_IO, "cannot set header attributes: %s",
                          exr_get_error_code_as_string(rc));
  return SATF_OK;
}

/* The part's planes: one per channel, count samples tall. */
static satf_status planes_alloc(const satf_db_part *q, const char *path,
                                float **planes, satf_error *err) {
  const satf_build_params *p = &q->p;
  int nc = satf_build_params_channels(p);
  size_t n = (size_t)q->count * (size_t)p->n_light * (size_t)p->n_view *
             (size_t)p->trace.width;
  int ok = 1;
  for (int c = 0; c < nc; c++)
    ok = ok && (planes[c] = malloc(n * sizeof(float))) != NULL;
  if (ok)
    return SATF_OK;
  for (int c = 0; c < nc; c++)
    free(planes[c]);
  return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
}

satf_status satf_db_part_write(satf_db_part *part, const char *path,
                               satf_error *err) {
  const satf_build_params *p = &part->p;
  int nc = satf_build_params_channels(p);
  satf_db_round_half(part->rec, (size_t)part->count * satf_db_sample_floats(p));
  float *planes[SATF_DB_MAX_CHANNELS] = {NULL};
  satf_status st = planes_alloc(part, path, planes, err);
  if (st != SATF_OK)
    return st;
  satf_db_channels_copy(p, part->count, part->rec, planes, 1);
  char names[SATF_DB_MAX_CHANNELS][SATF_DB_CHANNEL_NAME];
  satf_db_channel_names(p, names);
  satf_exr_channel ch[SATF_DB_MAX_CHANNELS];
  for (int c = 0; c < nc; c++)
    ch[c] = (satf_exr_channel){names[c], planes[c]};
  satf_exr_write_opts opts = {EXR_PIXEL_HALF, EXR_COMPRESSION_ZIP, write_attrs,
                              part, 0};
  st = satf_exr_write(path, p->n_view * p->trace.width,
                      part->count * p->n_light, ch, nc, &opts, err);
  for (int c = 0; c < nc; c++)
    free(planes[c]);
  return st;
}

typedef struct read_ctx {
  const char *path;
  satf_db_part q; /* the header; features owned until adopted */
  uint64_t hash;
  int probe;  /* stop after the header (which channels to read) */
  int probed; /* the probe read it */
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
  int *place[4];
  place_fields(q, place);
  satf_status st = satf_db_format_attrs_read(path, exr, part, SHARD_FORMAT,
                                             "an satf database shard", err);
  if (st == SATF_OK)
    st = satf_db_params_attrs_read(path, exr, part, &q->p, err);
  if (st == SATF_OK)
    st = satf_db_hex_attr_read(path, exr, part, "satf:hash", &rc->hash, err);
  for (int i = 0; i < 4 && st == SATF_OK; i++)
    if (exr_attr_get_int(exr, part, PLACE_NAMES[i], place[i]) !=
        EXR_ERR_SUCCESS)
      st = satf_error_set(err, SATF_ERR_CORRUPT, "%s: missing %s", path,
                          PLACE_NAMES[i]);
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
  if (rc->probe) {
    rc->probed = 1;
    return satf_error_set(err, SATF_ERR_INTERNAL, "%s: header probed", path);
  }
  return satf_db_features_attr_read(path, exr, part, q->count, &q->features,
                                    err);
}

/* The header alone (a probe), then every channel of its record kind. */
satf_status satf_db_part_read(const char *path, satf_db_part **out,
                              satf_error *err) {
  *out = NULL;
  read_ctx rc;
  memset(&rc, 0, sizeof rc);
  rc.path = path;
  rc.probe = 1;
  int w = 0, h = 0;
  satf_error perr;
  satf_status st = satf_exr_read(path, NULL, 0, 1LL << 31, read_attrs, &rc, &w,
                                 &h, NULL, &perr);
  if (!rc.probed) {
    *err = perr;
    return st;
  }
  rc.probe = 0;
  int nc = satf_build_params_channels(&rc.q.p);
  char names[SATF_DB_MAX_CHANNELS][SATF_DB_CHANNEL_NAME];
  const char *name_of[SATF_DB_MAX_CHANNELS];
  float *planes[SATF_DB_MAX_CHANNELS] = {NULL};
  satf_db_channel_names(&rc.q.p, names);
  for (int c = 0; c < nc; c++)
    name_of[c] = names[c];
  st = satf_exr_read(path, name_of, nc, 1LL << 31, read_attrs, &rc, &w, &h,
                     planes, err);
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
    satf_db_channels_copy(&q->p, q->count, q->rec, planes, 0);
  for (int c = 0; c < nc; c++)
    free(planes[c]);
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
