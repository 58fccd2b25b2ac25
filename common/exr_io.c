/* exr_io.c - see exr_io.h. */
#include "satf/common.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Chunks encoded at once by satf_exr_write (write_chunks). */
#define EXR_BATCH 32

/* OpenEXRCore reports errors through a callback; keep the first message so
 * the satf_error can name the real cause rather than a bare code. */
typedef struct exr_msg {
  char text[512];
} exr_msg;

/* The handler cannot ask the context for its user data: OpenEXRCore calls it
 * with the context's mutex held (write contexts lock around every call) and
 * exr_get_user_data takes that mutex again, so the first write error (a
 * full disk) deadlocked satf-build and satf-render. The handler runs on the
 * thread that made the failing call, so each satf_exr_* call points this
 * thread-local sink at its own message for its duration. */
static _Thread_local exr_msg *current_msg;

static void capture_error(exr_const_context_t ctxt, exr_result_t code,
                          const char *msg) {
  (void)ctxt;
  exr_msg *m = current_msg;
  if (!m || m->text[0] != '\0')
    return;
  snprintf(m->text, sizeof m->text, "%s",
           msg ? msg : exr_get_error_code_as_string(code));
  /* Messages can quote bytes of a damaged file: keep the terminal safe. */
  for (char *c = m->text; *c; c++)
    if ((unsigned char)*c < 0x20 || (unsigned char)*c > 0x7e)
      *c = '?';
}

static const char *describe(const exr_msg *m, exr_result_t rc) {
  return m->text[0] ? m->text : exr_get_error_code_as_string(rc);
}

/* The chunks of one batch, encoded on the pool's threads: OpenEXRCore
 * holds a write context's lock only while it packs a chunk and lets go
 * while it compresses, so chunks compress side by side (ZIP took 2.3 of the
 * fibre database build's 20 s on one thread: the build's serial tail); the
 * compressed chunks are then written in order by the calling thread. */
typedef struct chunk_batch {
  exr_context_t ctx;
  int part, width, lines, y0;
  const satf_exr_channel *channels;
  int nchannels;
  exr_encode_pipeline_t enc[EXR_BATCH];
  exr_result_t rc[EXR_BATCH];
} chunk_batch;

/* The pipeline's last steps, replaced: waiting for the chunks before it
 * (by default an error unless this chunk is the next the file takes) and
 * writing it; the chunk stays in its buffers for the calling thread to
 * write in order. */
static exr_result_t keep_chunk(exr_encode_pipeline_t *enc) {
  (void)enc;
  return EXR_ERR_SUCCESS;
}

static int encode_chunk(void *ctx, size_t i, int thread) {
  (void)thread;
  chunk_batch *b = ctx;
  exr_encode_pipeline_t *enc = &b->enc[i];
  exr_chunk_info_t cinfo;
  int y = b->y0 + (int)i * b->lines;
  exr_result_t rc = exr_write_scanline_chunk_info(b->ctx, b->part, y, &cinfo);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_encoding_initialize(b->ctx, b->part, &cinfo, enc);
  for (int e = 0; rc == EXR_ERR_SUCCESS && e < enc->channel_count; e++) {
    const float *src = NULL;
    for (int c = 0; c < b->nchannels; c++)
      if (strcmp(b->channels[c].name, enc->channels[e].channel_name) == 0)
        src = b->channels[c].data;
    enc->channels[e].user_bytes_per_element = 4;
    enc->channels[e].user_data_type = EXR_PIXEL_FLOAT;
    enc->channels[e].user_pixel_stride = 4;
    enc->channels[e].user_line_stride = 4 * b->width;
    enc->channels[e].encode_from_ptr =
        (const uint8_t *)(src + (size_t)(cinfo.start_y) * (size_t)b->width);
  }
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_encoding_choose_default_routines(b->ctx, b->part, enc);
  if (rc == EXR_ERR_SUCCESS) {
    enc->yield_until_ready_fn = keep_chunk;
    enc->write_fn = keep_chunk;
    rc = exr_encoding_run(b->ctx, b->part, enc);
  }
  b->rc[i] = rc;
  return 0;
}

/* Every chunk of the image, EXR_BATCH at a time. */
static exr_result_t write_chunks(exr_context_t ctx, int part, int width,
                                 int height, int lines,
                                 const satf_exr_channel *channels,
                                 int nchannels, int threads) {
  chunk_batch *b = calloc(1, sizeof *b);
  if (!b)
    return EXR_ERR_OUT_OF_MEMORY;
  *b = (chunk_batch){.ctx = ctx,
                     .part = part,
                     .width = width,
                     .lines = lines,
                     .channels = channels,
                     .nchannels = nchannels};
  exr_result_t rc = EXR_ERR_SUCCESS;
  for (int y0 = 0; y0 < height && rc == EXR_ERR_SUCCESS;
       y0 += EXR_BATCH * lines) {
    int n = (height - y0 + lines - 1) / lines;
    n = n < EXR_BATCH ? n : EXR_BATCH;
    b->y0 = y0;
    for (int i = 0; i < n; i++)
      b->enc[i] = (exr_encode_pipeline_t)EXR_ENCODE_PIPELINE_INITIALIZER;
    satf_parallel_for((size_t)n, threads, encode_chunk, b, NULL, NULL);
    for (int i = 0; i < n; i++) {
      exr_encode_pipeline_t *enc = &b->enc[i];
      if (rc == EXR_ERR_SUCCESS)
        rc = b->rc[i];
      if (rc == EXR_ERR_SUCCESS)
        rc = exr_write_scanline_chunk(ctx, part, enc->chunk.start_y,
                                      enc->compressed_buffer,
                                      enc->compressed_bytes);
      if (enc->context)
        exr_encoding_destroy(ctx, enc);
    }
  }
  free(b);
  return rc;
}

static satf_status exr_write(const char *path, int width, int height,
                             const satf_exr_channel *channels,
                             const exr_pixel_type_t *types, int nchannels,
                             const satf_exr_write_opts *opts, exr_msg *msg,
                             satf_error *err) {
  if (width <= 0 || height <= 0 || nchannels <= 0 || nchannels > 64)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: invalid image size %dx%d or channel count %d",
                          path, width, height, nchannels);
  char tmp[4096];
  satf_status st = satf_temp_path(path, tmp, sizeof tmp, err);
  if (st != SATF_OK)
    return st;

  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = capture_error;
  exr_context_t ctx = NULL;
  exr_result_t rc = exr_start_write(&ctx, tmp, EXR_WRITE_FILE_DIRECTLY, &init);
  if (rc != EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot create: %s", path,
                          describe(msg, rc));
  int part = 0;
  st = SATF_OK;
  rc = exr_add_part(ctx, "satf", EXR_STORAGE_SCANLINE, &part);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_initialize_required_attr_simple(ctx, part, width, height,
                                             opts->compression);
  for (int c = 0; c < nchannels && rc == EXR_ERR_SUCCESS; c++)
    rc = exr_add_channel(ctx, part, channels[c].name,
                         types ? types[c] : opts->pixel_type,
                         EXR_PERCEPTUALLY_LINEAR, 1, 1);
  if (rc == EXR_ERR_SUCCESS && opts->attrs)
    st = opts->attrs(opts->attrs_ctx, ctx, part, err);
  if (rc == EXR_ERR_SUCCESS && st == SATF_OK)
    rc = exr_write_header(ctx);

  int32_t lines = 1;
  if (rc == EXR_ERR_SUCCESS && st == SATF_OK)
    rc = exr_get_scanlines_per_chunk(ctx, part, &lines);
  if (rc == EXR_ERR_SUCCESS && st == SATF_OK)
    rc = write_chunks(ctx, part, width, height, lines, channels, nchannels,
                      opts->threads);
  exr_result_t frc = exr_finish(&ctx);
  if (st == SATF_OK && rc == EXR_ERR_SUCCESS && frc != EXR_ERR_SUCCESS)
    rc = frc;
  if (st != SATF_OK || rc != EXR_ERR_SUCCESS) {
    remove(tmp);
    if (st != SATF_OK)
      return st;
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot write: %s", path,
                          describe(msg, rc));
  }
  return satf_commit_temp(tmp, path, err);
}

satf_status satf_exr_write(const char *path, int width, int height,
                           const satf_exr_channel *channels, int nchannels,
                           const satf_exr_write_opts *opts, satf_error *err) {
  exr_msg msg = {{0}}, *outer = current_msg;
  current_msg = &msg;
  satf_status st = exr_write(path, width, height, channels, NULL, nchannels,
                             opts, &msg, err);
  current_msg = outer;
  return st;
}

satf_status satf_exr_write_typed(const char *path, int width, int height,
                                 const satf_exr_channel *channels,
                                 const exr_pixel_type_t *types, int nchannels,
                                 const satf_exr_write_opts *opts,
                                 satf_error *err) {
  exr_msg msg = {{0}}, *outer = current_msg;
  current_msg = &msg;
  satf_status st = exr_write(path, width, height, channels, types, nchannels,
                             opts, &msg, err);
  current_msg = outer;
  return st;
}

/* Opens path and checks it is a single-part scanline image whose size the
 * file could plausibly hold; *dw receives the data window. */
static satf_status open_checked(const char *path, long long fsize,
                                long long max_pixels, const exr_msg *msg,
                                exr_context_t *ctx, exr_attr_box2i_t *dw,
                                satf_error *err) {
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = capture_error;
  exr_result_t rc = exr_start_read(ctx, path, &init);
  if (rc != EXR_ERR_SUCCESS) {
    satf_status code =
        rc == EXR_ERR_FILE_ACCESS ? SATF_ERR_IO : SATF_ERR_FORMAT;
    return satf_error_set(err, code, "%s: not a readable OpenEXR file: %s",
                          path, describe(msg, rc));
  }
  int parts = 0;
  exr_storage_t storage = EXR_STORAGE_LAST_TYPE;
  memset(dw, 0, sizeof *dw);
  exr_get_count(*ctx, &parts);
  if (parts != 1 || exr_get_storage(*ctx, 0, &storage) != EXR_ERR_SUCCESS ||
      storage != EXR_STORAGE_SCANLINE ||
      exr_get_data_window(*ctx, 0, dw) != EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: expected a single-part scanline OpenEXR image",
                          path);
  long long w = (long long)dw->max.x - dw->min.x + 1;
  long long h = (long long)dw->max.y - dw->min.y + 1;
  /* Deflate cannot expand data by more than ~1032:1, so a header promising
   * far more pixels than the file could hold is corrupt: refuse it before
   * allocating anything. */
  long long raw = w * h * 2;
  if (w <= 0 || h <= 0 || w > (1 << 24) || h > (1 << 24) ||
      w * h > max_pixels || raw / 1100 > fsize)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: implausible image size %lldx%lld for a file of "
                          "%lld bytes",
                          path, w, h, fsize);
  return SATF_OK;
}

/* Whether the file's channel `have` is the one asked for as `want`: the
 * same name, or, in a file of one view layer written as Blender and Nuke
 * write them (LAYER.PASS.CHANNEL, satf/render.h), LAYER.want, or
 * LAYER.Combined.want / LAYER.Depth.want for an unlayered want. */
static int channel_matches(const char *have, const char *want) {
  if (strcmp(have, want) == 0)
    return 1;
  const char *dot = strchr(have, '.');
  if (!dot || dot == have)
    return 0;
  const char *rest = dot + 1;
  if (strcmp(rest, want) == 0)
    return 1;
  if (strchr(want, '.'))
    return 0;
  static const char *const passes[2] = {"Combined.", "Depth."};
  for (int k = 0; k < 2; k++) {
    size_t n = strlen(passes[k]);
    if (strncmp(rest, passes[k], n) == 0 && strcmp(rest + n, want) == 0)
      return 1;
  }
  return 0;
}

/* Every requested channel is present at full resolution: resolved[i] is
 * the file's name for names[i] (an exact match first). */
static satf_status check_channels(const char *path, exr_const_context_t ctx,
                                  const char *const *names, int nnames,
                                  const char **resolved, satf_error *err) {
  const exr_attr_chlist_t *chlist = NULL;
  if (exr_get_channels(ctx, 0, &chlist) != EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_FORMAT, "%s: no channel list", path);
  for (int i = 0; i < nnames; i++) {
    int found = 0;
    resolved[i] = NULL;
    for (int exact = 1; exact >= 0 && !resolved[i]; exact--)
      for (int c = 0; c < chlist->num_channels && !resolved[i]; c++) {
        const char *have = chlist->entries[c].name.str;
        if (exact ? strcmp(have, names[i]) == 0
                  : channel_matches(have, names[i])) {
          resolved[i] = have;
          found = chlist->entries[c].x_sampling == 1 &&
                  chlist->entries[c].y_sampling == 1;
        }
      }
    if (!found)
      return satf_error_set(err, SATF_ERR_FORMAT,
                            "%s: channel '%s' is missing or subsampled", path,
                            names[i]);
  }
  return SATF_OK;
}

/* Where each channel of a chunk decodes to: the requested planes, and a
 * scratch buffer (grown as needed) for the channels nobody asked for. */
typedef struct decode_target {
  const char *const *names;
  int nnames;
  float **planes;
  long long width;
  float *scratch;
  size_t scratch_size;
} decode_target;

static exr_result_t decode_chunk(exr_const_context_t ctx,
                                 const exr_chunk_info_t *cinfo, long long row0,
                                 decode_target *dt) {
  exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
  exr_result_t rc = exr_decoding_initialize(ctx, 0, cinfo, &dec);
  /* Channels nobody asked for are decoded into scratch: OpenEXRCore 3.1 can
   * crash converting a chunk when some channels are skipped (NULL
   * decode_to_ptr) and others converted from half. */
  size_t need = (size_t)dt->width * (size_t)cinfo->height;
  if (rc == EXR_ERR_SUCCESS && need > dt->scratch_size) {
    float *grown = realloc(dt->scratch, need * sizeof(float));
    if (grown) {
      dt->scratch = grown;
      dt->scratch_size = need;
    } else {
      rc = EXR_ERR_OUT_OF_MEMORY;
    }
  }
  for (int e = 0; rc == EXR_ERR_SUCCESS && e < dec.channel_count; e++) {
    dec.channels[e].decode_to_ptr = (uint8_t *)dt->scratch;
    for (int i = 0; i < dt->nnames; i++)
      if (strcmp(dt->names[i], dec.channels[e].channel_name) == 0)
        dec.channels[e].decode_to_ptr =
            (uint8_t *)(dt->planes[i] + row0 * dt->width);
    dec.channels[e].user_bytes_per_element = 4;
    dec.channels[e].user_data_type = EXR_PIXEL_FLOAT;
    dec.channels[e].user_pixel_stride = 4;
    dec.channels[e].user_line_stride = (int32_t)(4 * dt->width);
  }
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_decoding_choose_default_routines(ctx, 0, &dec);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_decoding_run(ctx, 0, &dec);
  exr_decoding_destroy(ctx, &dec);
  return rc;
}

static satf_status decode_all(const char *path, exr_const_context_t ctx,
                              const exr_attr_box2i_t *dw, const exr_msg *msg,
                              decode_target *dt, satf_error *err) {
  long long h = (long long)dw->max.y - dw->min.y + 1;
  int32_t lines = 1;
  if (exr_get_scanlines_per_chunk(ctx, 0, &lines) != EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_FORMAT, "%s: bad chunk layout", path);
  for (long long y = dw->min.y; y <= dw->max.y; y += lines) {
    exr_chunk_info_t cinfo;
    long long row0 = 0;
    exr_result_t rc = exr_read_scanline_chunk_info(ctx, 0, (int)y, &cinfo);
    if (rc == EXR_ERR_SUCCESS) {
      row0 = (long long)cinfo.start_y - dw->min.y;
      if (row0 < 0 || row0 + cinfo.height > h)
        rc = EXR_ERR_CORRUPT_CHUNK;
    }
    if (rc == EXR_ERR_SUCCESS)
      rc = decode_chunk(ctx, &cinfo, row0, dt);
    if (rc != EXR_ERR_SUCCESS)
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: cannot decode scanlines at y=%lld: %s", path,
                            y, describe(msg, rc));
  }
  return SATF_OK;
}

static satf_status exr_read(const char *path, const char *const *names,
                            int nnames, long long max_pixels,
                            satf_exr_attr_reader attrs, void *attrs_ctx,
                            int *width_out, int *height_out, float **planes,
                            const exr_msg *msg, satf_error *err) {
  struct stat sb;
  if (stat(path, &sb) != 0)
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot open: %s", path,
                          strerror(errno));
  if (!S_ISREG(sb.st_mode))
    return satf_error_set(err, SATF_ERR_IO, "%s: not a regular file", path);
  long long fsize = (long long)sb.st_size;
  exr_context_t ctx = NULL;
  exr_attr_box2i_t dw;
  memset(&dw, 0, sizeof dw);
  satf_status st = open_checked(path, fsize, max_pixels, msg, &ctx, &dw, err);
  long long w = (long long)dw.max.x - dw.min.x + 1;
  long long h = (long long)dw.max.y - dw.min.y + 1;
  if (st == SATF_OK && attrs)
    st = attrs(attrs_ctx, ctx, 0, (int)w, (int)h, err);
  const char **resolved =
      malloc((size_t)(nnames > 0 ? nnames : 1) * sizeof *resolved);
  if (st == SATF_OK && !resolved)
    st = satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  if (st == SATF_OK)
    st = check_channels(path, ctx, names, nnames, resolved, err);
  for (int i = 0; i < nnames && st == SATF_OK; i++) {
    planes[i] = malloc((size_t)(w * h) * sizeof(float));
    if (!planes[i])
      st = satf_error_set(err, SATF_ERR_NOMEM,
                          "%s: cannot allocate %lldx%lld pixels", path, w, h);
  }
  decode_target dt = {resolved, nnames, planes, w, NULL, 0};
  if (st == SATF_OK)
    st = decode_all(path, ctx, &dw, msg, &dt, err);
  free(dt.scratch);
  free(resolved);
  exr_finish(&ctx);
  if (st != SATF_OK)
    return st;
  *width_out = (int)w;
  *height_out = (int)h;
  return SATF_OK;
}

satf_status satf_exr_read(const char *path, const char *const *names,
                          int nnames, long long max_pixels,
                          satf_exr_attr_reader attrs, void *attrs_ctx,
                          int *width_out, int *height_out, float **planes,
                          satf_error *err) {
  for (int i = 0; i < nnames; i++)
    planes[i] = NULL;
  exr_msg msg = {{0}}, *outer = current_msg;
  current_msg = &msg;
  satf_status st = exr_read(path, names, nnames, max_pixels, attrs, attrs_ctx,
                            width_out, height_out, planes, &msg, err);
  current_msg = outer;
  if (st != SATF_OK)
    for (int i = 0; i < nnames; i++) {
      free(planes[i]);
      planes[i] = NULL;
    }
  return st;
}
