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

/* Format version 2: the record kind and the fibre tracer's parameters
 * (satf:kind "fiber", satf:eta, satf:betaN, satf:subRays, satf:maxBounces,
 * satf:absorption = the levels' sigma_a). */
static exr_result_t fiber_attrs_write(exr_context_t exr, int part,
                                      const satf_build_params *p) {
  const satf_fiber_trace_params *f = &p->fiber;
  exr_result_t rc = exr_attr_set_string(exr, part, "satf:kind",
                                        satf_record_kind_name(p->kind));
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_float(exr, part, "satf:eta", f->eta);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_float(exr, part, "satf:betaN", f->beta_n);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_int(exr, part, "satf:subRays", f->sub_rays);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_int(exr, part, "satf:maxBounces", f->max_bounces);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_float_vector(exr, part, "satf:absorption", f->levels,
                                   f->sigma_a);
  return rc;
}

/* The reader of fiber_attrs_write; a file without satf:kind holds Phong
 * records, and a version 1 file can hold nothing else. */
static satf_status fiber_attrs_read(const char *path, exr_const_context_t exr,
                                    int part, satf_build_params *p,
                                    satf_error *err) {
  const char *s = NULL;
  int32_t len = 0, version = 0;
  char kind[16] = "phong";
  if (exr_attr_get_string(exr, part, "satf:kind", &len, &s) ==
      EXR_ERR_SUCCESS) {
    if (len <= 0 || len >= (int32_t)sizeof kind)
      return satf_error_set(err, SATF_ERR_CORRUPT, "%s: malformed satf:kind",
                            path);
    memcpy(kind, s, (size_t)len);
    kind[len] = 0;
  }
  if (satf_record_kind_parse(kind, &p->kind) != 0)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: unknown record kind \"%s\" (satf:kind)", path,
                          kind);
  p->fiber = satf_fiber_trace_params_default();
  if (p->kind != SATF_RECORD_FIBER)
    return SATF_OK;
  if (exr_attr_get_int(exr, part, "satf:version", &version) !=
          EXR_ERR_SUCCESS ||
      version < 2)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: fibre records in a file of format version %d "
                          "(they need version 2)",
                          path, version);
  satf_fiber_trace_params *f = &p->fiber;
  int32_t nl = 0;
  const float *levels = NULL;
  if (exr_attr_get_float(exr, part, "satf:eta", &f->eta) != EXR_ERR_SUCCESS ||
      exr_attr_get_float(exr, part, "satf:betaN", &f->beta_n) !=
          EXR_ERR_SUCCESS ||
      exr_attr_get_int(exr, part, "satf:subRays", &f->sub_rays) !=
          EXR_ERR_SUCCESS ||
      exr_attr_get_int(exr, part, "satf:maxBounces", &f->max_bounces) !=
          EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: fibre records without satf:eta, satf:betaN, "
                          "satf:subRays or satf:maxBounces",
                          path);
  if (exr_attr_get_float_vector(exr, part, "satf:absorption", &nl, &levels) !=
          EXR_ERR_SUCCESS ||
      nl < 1 || nl > SATF_DB_LEVELS_MAX)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: satf:absorption missing or not 1 to %d levels",
                          path, SATF_DB_LEVELS_MAX);
  f->levels = nl;
  memcpy(f->sigma_a, levels, (size_t)nl * sizeof(float));
  return SATF_OK;
}

exr_result_t satf_db_params_attrs_write(exr_context_t exr, int part,
                                        const satf_build_params *params) {
  satf_build_params p = *params;
  int_attr ints[] = INT_ATTRS(&p);
  float_attr floats[] = FLOAT_ATTRS(&p);
  char seed[32];
  snprintf(seed, sizeof seed, "%016" PRIx64, p.seed);
  exr_result_t rc = exr_attr_set_string(exr, part, "satf:seed", seed);
  for (int i = 0; i < COUNT(ints) && rc == EXR_ERR_SUCCESS; i++)
    rc = exr_attr_set_int(exr, part, ints[i].name, *ints[i].field);
  for (int i = 0; i < COUNT(floats) && rc == EXR_ERR_SUCCESS; i++)
    rc = exr_attr_set_float(exr, part, floats[i].name, *floats[i].field);
  /* the version of the records' kind (1 for Phong), over the newest that
   * satf_db_format_attrs_write wrote before */
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_int(exr, part, "satf:version",
                          satf_build_params_version(&p));
  if (rc == EXR_ERR_SUCCESS && p.kind == SATF_RECORD_FIBER)
    rc = fiber_attrs_write(exr, part, &p);
  return rc;
}

exr_result_t satf_db_format_attrs_write(exr_context_t exr, int part,
                                        const char *format, uint64_t hash) {
  char hex[32];
  snprintf(hex, sizeof hex, "%016" PRIx64, hash);
  exr_result_t rc = exr_attr_set_string(exr, part, "satf:format", format);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_int(exr, part, "satf:version", SATF_DB_FORMAT_VERSION);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_string(exr, part, "satf:generator",
                             "satf " SATF_VERSION_STRING);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_string(exr, part, "satf:hash", hex);
  return rc;
}

static satf_status write_attrs(void *ctx, exr_context_t exr, int part,
                               satf_error *err) {
  const satf_db *db = ctx;
  exr_result_t rc = satf_db_format_attrs_write(exr, part, FORMAT_NAME,
                                               satf_db_payload_hash(db));
  if (rc == EXR_ERR_SUCCESS)
    rc = satf_db_params_attrs_write(exr, part, &db->p);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_attr_set_float_vector(exr, part, "satf:features",
                                   db->p.samples * SATF_FEATURES, db->features);
  if (rc != EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_IO, "cannot set header attributes: %s",
                          exr_get_error_code_as_string(rc));
  return SATF_OK;
}

/* ---- every channel (format version 2) ---- */
#define MAX_CHANNELS SATF_DB_MAX_CHANNELS

/* The file's channel names in the order of a record's channels
 * (SATF_DB_CH_*): Y reflectance and A alpha as in version 1, so a viewer
 * shows a fibre database's total as a luminance-alpha picture; the lobes
 * as R_lobe, TT0.., TRT0.., MS0.. (level index). */
typedef struct channel_names {
  char name[MAX_CHANNELS][SATF_DB_CHANNEL_NAME];
} channel_names;

static void channel_names_of(const satf_build_params *p, channel_names *n) {
  snprintf(n->name[SATF_DB_CH_REFLECTANCE], 16, "Y");
  snprintf(n->name[SATF_DB_CH_ALPHA], 16, "A");
  if (p->kind != SATF_RECORD_FIBER)
    return;
  int K = p->fiber.levels;
  snprintf(n->name[SATF_DB_CH_R], 16, "R_lobe");
  for (int k = 0; k < K; k++) {
    snprintf(n->name[SATF_DB_CH_TT(k)], 16, "TT%d", k);
    snprintf(n->name[SATF_DB_CH_TRT(k, K)], 16, "TRT%d", k);
    snprintf(n->name[SATF_DB_CH_MS(k, K)], 16, "MS%d", k);
  }
}

void satf_db_channel_names(const satf_build_params *p,
                           char names[][SATF_DB_CHANNEL_NAME]) {
  channel_names n;
  channel_names_of(p, &n);
  memcpy(names, n.name, sizeof n.name);
}

/* Copies every channel between memory (rec, satf_db_record_offset's
 * layout) and one image plane per channel (the pixel layout above). */
void satf_db_channels_copy(const satf_build_params *p, int samples, float *rec,
                           float *const *planes, int to_planes) {
  int nc = satf_build_params_channels(p);
  size_t w = (size_t)p->trace.width, row = (size_t)p->n_view * w;
  for (int i = 0; i < samples; i++)
    for (int il = 0; il < p->n_light; il++)
      for (int iv = 0; iv < p->n_view; iv++) {
        size_t rec_i = (size_t)i * (size_t)p->n_light + (size_t)il;
        float *r =
            rec + (rec_i * (size_t)p->n_view + (size_t)iv) * (size_t)nc * w;
        size_t px = rec_i * row + (size_t)iv * w;
        for (int c = 0; c < nc; c++) {
          if (to_planes)
            memcpy(planes[c] + px, r + (size_t)c * w, w * sizeof(float));
          else
            memcpy(r + (size_t)c * w, planes[c] + px, w * sizeof(float));
        }
      }
}

static void channels_copy(const satf_build_params *p, float *rec,
                          float *const *planes, int to_planes) {
  satf_db_channels_copy(p, p->samples, rec, planes, to_planes);
}

static satf_status write_image(const satf_db *db, const char *path, int rgba,
                               int threads, satf_error *err) {
  if (!db->tree)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: database was not finalized before writing",
                          path);
  int nc = satf_build_params_channels(&db->p);
  size_t n = (size_t)db->p.samples * db->p.n_light * db->p.n_view *
             (size_t)db->p.trace.width;
  float *planes[MAX_CHANNELS] = {NULL};
  int ok = 1;
  for (int c = 0; c < nc; c++)
    ok = ok && (planes[c] = malloc(n * sizeof(float))) != NULL;
  if (!ok) {
    for (int c = 0; c < nc; c++)
      free(planes[c]);
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  }
  channels_copy(&db->p, db->rec, planes, 1);
  float *re = planes[SATF_DB_CH_REFLECTANCE], *alpha = planes[SATF_DB_CH_ALPHA];
  channel_names names;
  satf_exr_channel db_ch[MAX_CHANNELS];
  channel_names_of(&db->p, &names);
  for (int c = 0; c < nc; c++)
    db_ch[c] = (satf_exr_channel){names.name[c], planes[c]};
  satf_exr_channel atlas_ch[4] = {
      {"R", re}, {"G", re}, {"B", re}, {"A", alpha}};
  satf_exr_write_opts opts = {EXR_PIXEL_HALF, EXR_COMPRESSION_ZIP,
                              rgba ? NULL : write_attrs, (void *)db, threads};
  satf_status st = satf_exr_write(
      path, db->p.n_view * db->p.trace.width, db->p.samples * db->p.n_light,
      rgba ? atlas_ch : db_ch, rgba ? 4 : nc, &opts, err);
  for (int c = 0; c < nc; c++)
    free(planes[c]);
  return st;
}

satf_status satf_db_write(const satf_db *db, const char *path,
                          satf_error *err) {
  return write_image(db, path, 0, 0, err);
}

satf_status satf_db_write_threads(const satf_db *db, const char *path,
                                  int threads, satf_error *err) {
  return write_image(db, path, 0, threads, err);
}

satf_status satf_db_write_atlas(const satf_db *db, const char *path,
                                satf_error *err) {
  return write_image(db, path, 1, 0, err);
}

typedef struct read_ctx {
  const char *path;
  satf_build_params p;
  uint64_t hash;
  float *features;
  int probe;  /* stop after the parameters (which channels to read) */
  int probed; /* the probe read them */
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

satf_status satf_db_hex_attr_read(const char *path, exr_const_context_t exr,
                                  int part, const char *name, uint64_t *out,
                                  satf_error *err) {
  const char *s = NULL;
  int32_t len = 0;
  if (exr_attr_get_string(exr, part, name, &len, &s) != EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: missing %s", path, name);
  return parse_hex64(path, name, s, len, out, err);
}

satf_status satf_db_format_attrs_read(const char *path, exr_const_context_t exr,
                                      int part, const char *format,
                                      const char *what, satf_error *err) {
  const char *s = NULL;
  int32_t len = 0, version = 0;
  if (exr_attr_get_string(exr, part, "satf:format", &len, &s) !=
          EXR_ERR_SUCCESS ||
      len != (int32_t)strlen(format) || memcmp(s, format, (size_t)len) != 0)
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: an OpenEXR image, but not %s (no satf:format "
                          "attribute \"%s\")",
                          path, what, format);
  if (exr_attr_get_int(exr, part, "satf:version", &version) != EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: missing satf:version",
                          path);
  if (version < 1 || version > SATF_DB_FORMAT_VERSION)
    return satf_error_set(err, SATF_ERR_VERSION,
                          "%s: database format version %d; this satf reads "
                          "versions 1 to %d (rebuild it with satf-build)",
                          path, version, SATF_DB_FORMAT_VERSION);
  return SATF_OK;
}

satf_status satf_db_params_attrs_read(const char *path, exr_const_context_t exr,
                                      int part, satf_build_params *p,
                                      satf_error *err) {
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
  satf_status st =
      satf_db_hex_attr_read(path, exr, part, "satf:seed", &p->seed, err);
  if (st == SATF_OK)
    st = fiber_attrs_read(path, exr, part, p, err);
  if (st != SATF_OK)
    return st;
  satf_error perr;
  if (satf_build_params_check(p, &perr) != SATF_OK)
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: invalid parameters: %s",
                          path, perr.message);
  return SATF_OK;
}

satf_status satf_db_features_attr_read(const char *path,
                                       exr_const_context_t exr, int part,
                                       int samples, float **out,
                                       satf_error *err) {
  int32_t nf = 0;
  const float *fv = NULL;
  if (exr_attr_get_float_vector(exr, part, "satf:features", &nf, &fv) !=
          EXR_ERR_SUCCESS ||
      nf != samples * SATF_FEATURES)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: satf:features missing or not %d values", path,
                          samples * SATF_FEATURES);
  *out = malloc((size_t)nf * sizeof(float));
  if (!*out)
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  memcpy(*out, fv, (size_t)nf * sizeof(float));
  return SATF_OK;
}

static satf_status read_attrs(void *vctx, exr_const_context_t exr, int part,
                              int width, int height, satf_error *err) {
  read_ctx *rc = vctx;
  const char *path = rc->path;
  satf_build_params *p = &rc->p;
  satf_status st = satf_db_format_attrs_read(path, exr, part, FORMAT_NAME,
                                             "an satf HRIR database", err);
  if (st == SATF_OK)
    st = satf_db_params_attrs_read(path, exr, part, p, err);
  if (st == SATF_OK && rc->probe) {
    rc->probed = 1;
    return SATF_ERR_INTERNAL; /* not an error: stops the probe's read */
  }
  if (st == SATF_OK)
    st = satf_db_hex_attr_read(path, exr, part, "satf:hash", &rc->hash, err);
  if (st != SATF_OK)
    return st;
  if ((long long)width != (long long)p->n_view * p->trace.width ||
      (long long)height != (long long)p->samples * p->n_light)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: image is %dx%d but the parameters say %dx%d",
                          path, width, height, p->n_view * p->trace.width,
                          p->samples * p->n_light);
  return satf_db_features_attr_read(path, exr, part, p->samples, &rc->features,
                                    err);
}

satf_status satf_db_read(const char *path, satf_db **out, satf_error *err) {
  *out = NULL;
  /* The channels to read depend on the record kind in the header: a first
   * pass reads the header only. */
  read_ctx rc = {path, {0}, 0, NULL, 1, 0};
  int w = 0, h = 0;
  satf_error perr;
  satf_status st = satf_exr_read(path, NULL, 0, 1LL << 31, read_attrs, &rc, &w,
                                 &h, NULL, &perr);
  if (!rc.probed) {
    *err = perr;
    return st;
  }
  channel_names names;
  channel_names_of(&rc.p, &names);
  int nc = satf_build_params_channels(&rc.p);
  const char *name_of[MAX_CHANNELS];
  float *planes[MAX_CHANNELS] = {NULL};
  for (int c = 0; c < nc; c++)
    name_of[c] = names.name[c];
  rc.probe = 0;
  st = satf_exr_read(path, name_of, nc, 1LL << 31, read_attrs, &rc, &w, &h,
                     planes, err);
  if (st != SATF_OK) {
    free(rc.features);
    return st;
  }
  satf_db *db = NULL;
  size_t n = (size_t)w * (size_t)h;
  float *rec = malloc((size_t)nc * n * sizeof(float));
  if (!rec) {
    for (int c = 0; c < nc; c++)
      free(planes[c]);
    free(rc.features);
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  }
  st = satf_db_adopt(&rc.p, rec, rc.features, &db, err);
  if (st == SATF_OK)
    channels_copy(&rc.p, rec, planes, 0);
  for (int c = 0; c < nc; c++)
    free(planes[c]);
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
