/* hrir_db_file.c - the HRIR-DB file: an OpenEXR image whose pixels are the
 * records, so any EXR viewer shows the database.
 *
 * Layout: width = n_view x record width, height = samples x n_light; pixel
 * (x = iv * width + j, y = sample * n_light + il) holds sample j of the
 * record (sample, iv, il): channel Y its reflectance, A its alpha, both half
 * floats, ZIP-compressed. Header attributes "satf:*" hold the format name
 * and version, every build parameter, the feature vectors and the integrity
 * hash (satf_db_payload_hash, as 16 hex digits). */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hrir_db_internal.h"
#include "satf/common.h"

#define FORMAT_NAME "satf-hrirdb"

typedef struct int_attr {
  const char *name;
  int *field;
} int_attr;
typedef struct float_attr {
  const char *name;
  float *field;
} float_attr;

/* The one table of scalar attributes, used by both writer and reader. */
#define INT_ATTRS(p)                                                           \
  {                                                                            \
    {"satf:samples", &(p)->samples}, {"satf:nView", &(p)->n_view},             \
        {"satf:nLight", &(p)->n_light}, {"satf:grid", &(p)->grid},             \
        {"satf:width", &(p)->trace.width}, {                                   \
      "satf:selfShadow", &(p)->trace.self_shadow                               \
    }                                                                          \
  }
#define FLOAT_ATTRS(p)                                                         \
  {                                                                            \
    {"satf:rInner", &(p)->shape.r_inner},                                      \
        {"satf:rOuter", &(p)->shape.r_outer},                                  \
        {"satf:phaseSpan", &(p)->shape.phase_span},                            \
        {"satf:extinction", &(p)->trace.extinction},                           \
        {"satf:ambient", &(p)->trace.ambient},                                 \
        {"satf:diffuse", &(p)->trace.diffuse},                                 \
        {"satf:specular", &(p)->trace.specular},                               \
        {"satf:shininess", &(p)->trace.shininess},                             \
        {"satf:epsilon", &(p)->trace.epsilon}, {                               \
      "satf:smoothRatio", &(p)->trace.smooth_ratio                             \
    }                                                                          \
  }
#define COUNT(a) ((int)(sizeof(a) / sizeof((a)[0])))

static satf_status write_attrs(void *ctx, exr_context_t exr, int part,
                               satf_error *err) {
  const satf_db *db = ctx;
  satf_build_params p = db->p;
  int_attr ints[] = INT_ATTRS(&p);
  float_attr floats[] = FLOAT_ATTRS(&p);
  char seed[32], hash[32];
  snprintf(seed, sizeof seed, "%016" PRIx64, p.seed);
  snprintf(hash, sizeof hash, "%016" PRIx64, satf_db_payload_hash(db));
  exr_result_t rc = exr_attr_set_string(exr, part, "satf:format", FORMAT_NAME);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_int(exr, part, "satf:version", SATF_DB_FORMAT_VERSION);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_string(exr, part, "satf:generator",
                             "satf " SATF_VERSION_STRING);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_string(exr, part, "satf:seed", seed);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_string(exr, part, "satf:hash", hash);
  for (int i = 0; i < COUNT(ints) && rc == EXR_ERR_SUCCESS; i++)
    rc = exr_attr_set_int(exr, part, ints[i].name, *ints[i].field);
  for (int i = 0; i < COUNT(floats) && rc == EXR_ERR_SUCCESS; i++)
    rc = exr_attr_set_float(exr, part, floats[i].name, *floats[i].field);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_float_vector(exr, part, "satf:features",
                                   p.samples * SATF_FEATURES, db->features);
  if (rc != EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_IO, "cannot set header attributes: %s",
                          exr_get_error_code_as_string(rc));
  return SATF_OK;
}

/* Copies records between memory (interleaved) and image planes, in the
 * pixel layout described at the top of this file. */
static void planes_copy(const satf_db *db, float *rec, float *re, float *alpha,
                        int to_planes) {
  const satf_build_params *p = &db->p;
  size_t w = (size_t)p->trace.width, row = (size_t)p->n_view * w;
  for (int i = 0; i < p->samples; i++)
    for (int il = 0; il < p->n_light; il++)
      for (int iv = 0; iv < p->n_view; iv++) {
        float *r = rec + satf_db_record_offset(db, i, iv, il);
        size_t px = ((size_t)i * (size_t)p->n_light + (size_t)il) * row +
                    (size_t)iv * w;
        if (to_planes) {
          memcpy(re + px, r, w * sizeof(float));
          memcpy(alpha + px, r + w, w * sizeof(float));
        } else {
          memcpy(r, re + px, w * sizeof(float));
          memcpy(r + w, alpha + px, w * sizeof(float));
        }
      }
}

static satf_status write_image(const satf_db *db, const char *path, int rgba,
                               satf_error *err) {
  if (!db->tree)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: database was not finalized before writing",
                          path);
  size_t n = (size_t)db->p.samples * db->p.n_light * db->p.n_view *
             (size_t)db->p.trace.width;
  float *re = malloc(n * sizeof(float)), *alpha = malloc(n * sizeof(float));
  if (!re || !alpha) {
    free(re);
    free(alpha);
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  }
  planes_copy(db, db->rec, re, alpha, 1);
  satf_exr_channel db_ch[2] = {{"A", alpha}, {"Y", re}};
  satf_exr_channel atlas_ch[4] = {
      {"R", re}, {"G", re}, {"B", re}, {"A", alpha}};
  satf_exr_write_opts opts = {EXR_PIXEL_HALF, EXR_COMPRESSION_ZIP,
                              rgba ? NULL : write_attrs, (void *)db};
  satf_status st = satf_exr_write(
      path, db->p.n_view * db->p.trace.width, db->p.samples * db->p.n_light,
      rgba ? atlas_ch : db_ch, rgba ? 4 : 2, &opts, err);
  free(re);
  free(alpha);
  return st;
}

satf_status satf_db_write(const satf_db *db, const char *path,
                          satf_error *err) {
  return write_image(db, path, 0, err);
}

satf_status satf_db_write_atlas(const satf_db *db, const char *path,
                                satf_error *err) {
  return write_image(db, path, 1, err);
}

typedef struct read_ctx {
  const char *path;
  satf_build_params p;
  uint64_t hash;
  float *features;
} read_ctx;

static satf_status parse_hex64(const char *path, const char *what,
                               const char *s, int32_t len, uint64_t *out,
                               satf_error *err) {
  uint64_t v = 0;
  if (len != 16)
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: malformed %s", path,
                          what);
  for (int i = 0; i < 16; i++) {
    char c = s[i];
    int d = c >= '0' && c <= '9'   ? c - '0'
            : c >= 'a' && c <= 'f' ? c - 'a' + 10
                                   : -1;
    if (d < 0)
      return satf_error_set(err, SATF_ERR_CORRUPT, "%s: malformed %s", path,
                            what);
    v = v << 4 | (uint64_t)d;
  }
  *out = v;
  return SATF_OK;
}

static satf_status read_attrs(void *vctx, exr_const_context_t exr, int part,
                              int width, int height, satf_error *err) {
  read_ctx *rc = vctx;
  const char *path = rc->path;
  const char *s = NULL;
  int32_t len = 0, version = 0;
  if (exr_attr_get_string(exr, part, "satf:format", &len, &s) !=
          EXR_ERR_SUCCESS ||
      len != (int32_t)strlen(FORMAT_NAME) ||
      memcmp(s, FORMAT_NAME, (size_t)len) != 0)
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: an OpenEXR image, but not an satf HRIR "
                          "database (no satf:format attribute)",
                          path);
  if (exr_attr_get_int(exr, part, "satf:version", &version) != EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: missing satf:version",
                          path);
  if (version != SATF_DB_FORMAT_VERSION)
    return satf_error_set(err, SATF_ERR_VERSION,
                          "%s: database format version %d; this satf reads "
                          "version %d (rebuild it with satf-build)",
                          path, version, SATF_DB_FORMAT_VERSION);
  satf_build_params *p = &rc->p;
  memset(p, 0, sizeof *p);
  int_attr ints[] = INT_ATTRS(p);
  float_attr floats[] = FLOAT_ATTRS(p);
  for (int i = 0; i < COUNT(ints); i++)
    if (exr_attr_get_int(exr, part, ints[i].name, ints[i].field) !=
        EXR_ERR_SUCCESS)
      return satf_error_set(err, SATF_ERR_CORRUPT, "%s: missing %s", path,
                            ints[i].name);
  for (int i = 0; i < COUNT(floats); i++)
    if (exr_attr_get_float(exr, part, floats[i].name, floats[i].field) !=
        EXR_ERR_SUCCESS)
      return satf_error_set(err, SATF_ERR_CORRUPT, "%s: missing %s", path,
                            floats[i].name);
  satf_status st;
  if (exr_attr_get_string(exr, part, "satf:seed", &len, &s) != EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: missing satf:seed", path);
  if ((st = parse_hex64(path, "satf:seed", s, len, &p->seed, err)) != SATF_OK)
    return st;
  if (exr_attr_get_string(exr, part, "satf:hash", &len, &s) != EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: missing satf:hash", path);
  if ((st = parse_hex64(path, "satf:hash", s, len, &rc->hash, err)) != SATF_OK)
    return st;
  satf_error perr;
  if (satf_build_params_check(p, &perr) != SATF_OK)
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: invalid parameters: %s",
                          path, perr.message);
  if ((long long)width != (long long)p->n_view * p->trace.width ||
      (long long)height != (long long)p->samples * p->n_light)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: image is %dx%d but the parameters say %dx%d",
                          path, width, height, p->n_view * p->trace.width,
                          p->samples * p->n_light);
  int32_t nf = 0;
  const float *fv = NULL;
  if (exr_attr_get_float_vector(exr, part, "satf:features", &nf, &fv) !=
          EXR_ERR_SUCCESS ||
      nf != p->samples * SATF_FEATURES)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: satf:features missing or not %d values", path,
                          p->samples * SATF_FEATURES);
  rc->features = malloc((size_t)nf * sizeof(float));
  if (!rc->features)
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  memcpy(rc->features, fv, (size_t)nf * sizeof(float));
  return SATF_OK;
}

satf_status satf_db_read(const char *path, satf_db **out, satf_error *err) {
  *out = NULL;
  read_ctx rc = {path, {0}, 0, NULL};
  const char *names[2] = {"A", "Y"};
  float *planes[2] = {NULL, NULL};
  int w = 0, h = 0;
  satf_status st = satf_exr_read(path, names, 2, 1LL << 31, read_attrs, &rc, &w,
                                 &h, planes, err);
  if (st != SATF_OK) {
    free(rc.features);
    return st;
  }
  satf_db *db = NULL;
  size_t n = (size_t)w * (size_t)h;
  float *rec = malloc(2 * n * sizeof(float));
  if (!rec) {
    free(planes[0]);
    free(planes[1]);
    free(rc.features);
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  }
  st = satf_db_adopt(&rc.p, rec, rc.features, &db, err);
  if (st == SATF_OK)
    planes_copy(db, rec, planes[1], planes[0], 0);
  free(planes[0]);
  free(planes[1]);
  if (st != SATF_OK)
    return st;
  uint64_t actual = satf_db_payload_hash(db);
  if (actual != rc.hash) {
    satf_db_destroy(db);
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: integrity check failed (stored hash %016" PRIx64
                          ", computed %016" PRIx64 "): the file is damaged",
                          path, rc.hash, actual);
  }
  satf_error ierr;
  st = satf_db_index(db, &ierr);
  if (st != SATF_OK) {
    satf_db_destroy(db);
    return satf_error_set(err, st, "%s: %s", path, ierr.message);
  }
  *out = db;
  return SATF_OK;
}
