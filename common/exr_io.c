/* exr_io.c - see exr_io.h. */
#include "satf/common.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* OpenEXRCore reports errors through a callback; keep the first message so
 * the satf_error can name the real cause rather than a bare code. */
typedef struct exr_msg {
  char text[512];
} exr_msg;

static void capture_error(exr_const_context_t ctxt, exr_result_t code,
                          const char *msg) {
  void *ud = NULL;
  if (exr_get_user_data(ctxt, &ud) == EXR_ERR_SUCCESS && ud) {
    exr_msg *m = ud;
    if (m->text[0] == '\0')
      snprintf(m->text, sizeof m->text, "%s",
               msg ? msg : exr_get_error_code_as_string(code));
  }
}

static const char *describe(const exr_msg *m, exr_result_t rc) {
  return m->text[0] ? m->text : exr_get_error_code_as_string(rc);
}

satf_status satf_exr_write(const char *path, int width, int height,
                           const satf_exr_channel *channels, int nchannels,
                           const satf_exr_write_opts *opts, satf_error *err) {
  if (width <= 0 || height <= 0 || nchannels <= 0 || nchannels > 64)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: invalid image size %dx%d or channel count %d",
                          path, width, height, nchannels);
  char tmp[4096];
  satf_status st = satf_temp_path(path, tmp, sizeof tmp, err);
  if (st != SATF_OK)
    return st;

  exr_msg msg = {{0}};
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = capture_error;
  init.user_data = &msg;
  exr_context_t ctx = NULL;
  exr_result_t rc = exr_start_write(&ctx, tmp, EXR_WRITE_FILE_DIRECTLY, &init);
  if (rc != EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot create: %s", path,
                          describe(&msg, rc));
  int part = 0;
  st = SATF_OK;
  rc = exr_add_part(ctx, "satf", EXR_STORAGE_SCANLINE, &part);
  if (rc == EXR_ERR_SUCCESS)
    rc = exr_initialize_required_attr_simple(ctx, part, width, height,
                                             opts->compression);
  for (int c = 0; c < nchannels && rc == EXR_ERR_SUCCESS; c++)
    rc = exr_add_channel(ctx, part, channels[c].name, opts->pixel_type,
                         EXR_PERCEPTUALLY_LINEAR, 1, 1);
  if (rc == EXR_ERR_SUCCESS && opts->attrs)
    st = opts->attrs(opts->attrs_ctx, ctx, part, err);
  if (rc == EXR_ERR_SUCCESS && st == SATF_OK)
    rc = exr_write_header(ctx);

  int32_t lines = 1;
  if (rc == EXR_ERR_SUCCESS && st == SATF_OK)
    rc = exr_get_scanlines_per_chunk(ctx, part, &lines);
  const exr_attr_chlist_t *chlist = NULL;
  if (rc == EXR_ERR_SUCCESS && st == SATF_OK)
    rc = exr_get_channels(ctx, part, &chlist);
  for (int y = 0; y < height && rc == EXR_ERR_SUCCESS && st == SATF_OK;
       y += lines) {
    exr_chunk_info_t cinfo;
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    rc = exr_write_scanline_chunk_info(ctx, part, y, &cinfo);
    if (rc == EXR_ERR_SUCCESS)
      rc = exr_encoding_initialize(ctx, part, &cinfo, &enc);
    if (rc != EXR_ERR_SUCCESS)
      break;
    for (int e = 0; e < enc.channel_count; e++) {
      const float *src = NULL;
      for (int c = 0; c < nchannels; c++)
        if (strcmp(channels[c].name, enc.channels[e].channel_name) == 0)
          src = channels[c].data;
      enc.channels[e].user_bytes_per_element = 4;
      enc.channels[e].user_data_type = EXR_PIXEL_FLOAT;
      enc.channels[e].user_pixel_stride = 4;
      enc.channels[e].user_line_stride = 4 * width;
      enc.channels[e].encode_from_ptr =
          (const uint8_t *)(src + (size_t)(cinfo.start_y) * (size_t)width);
    }
    rc = exr_encoding_choose_default_routines(ctx, part, &enc);
    if (rc == EXR_ERR_SUCCESS)
      rc = exr_encoding_run(ctx, part, &enc);
    exr_encoding_destroy(ctx, &enc);
  }
  exr_result_t frc = exr_finish(&ctx);
  if (st == SATF_OK && rc == EXR_ERR_SUCCESS && frc != EXR_ERR_SUCCESS)
    rc = frc;
  if (st != SATF_OK || rc != EXR_ERR_SUCCESS) {
    remove(tmp);
    if (st != SATF_OK)
      return st;
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot write: %s", path,
                          describe(&msg, rc));
  }
  return satf_commit_temp(tmp, path, err);
}

satf_status satf_exr_read(const char *path, const char *const *names,
                          int nnames, long long max_pixels,
                          satf_exr_attr_reader attrs, void *attrs_ctx,
                          int *width_out, int *height_out, float **planes,
                          satf_error *err) {
  for (int i = 0; i < nnames; i++)
    planes[i] = NULL;
  long long fsize = satf_file_size(path);
  if (fsize < 0)
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot open: no such file",
                          path);
  exr_msg msg = {{0}};
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = capture_error;
  init.user_data = &msg;
  exr_context_t ctx = NULL;
  exr_result_t rc = exr_start_read(&ctx, path, &init);
  if (rc != EXR_ERR_SUCCESS) {
    satf_status code =
        rc == EXR_ERR_FILE_ACCESS ? SATF_ERR_IO : SATF_ERR_FORMAT;
    exr_finish(&ctx);
    return satf_error_set(err, code, "%s: not a readable OpenEXR file: %s",
                          path, describe(&msg, rc));
  }
  satf_status st = SATF_OK;
  int parts = 0;
  exr_storage_t storage = EXR_STORAGE_LAST_TYPE;
  exr_attr_box2i_t dw;
  memset(&dw, 0, sizeof dw);
  exr_get_count(ctx, &parts);
  if (parts != 1 || exr_get_storage(ctx, 0, &storage) != EXR_ERR_SUCCESS ||
      storage != EXR_STORAGE_SCANLINE ||
      exr_get_data_window(ctx, 0, &dw) != EXR_ERR_SUCCESS) {
    exr_finish(&ctx);
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: expected a single-part scanline OpenEXR image",
                          path);
  }
  long long w = (long long)dw.max.x - dw.min.x + 1;
  long long h = (long long)dw.max.y - dw.min.y + 1;
  /* Deflate cannot expand data by more than ~1032:1, so a header promising
   * far more pixels than the file could hold is corrupt: refuse it before
   * allocating anything. */
  long long raw = w * h * 2;
  if (w <= 0 || h <= 0 || w > (1 << 24) || h > (1 << 24) ||
      w * h > max_pixels || raw / 1100 > fsize) {
    exr_finish(&ctx);
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: implausible image size %lldx%lld for a file of "
                          "%lld bytes",
                          path, w, h, fsize);
  }
  if (attrs)
    st = attrs(attrs_ctx, ctx, 0, (int)w, (int)h, err);
  const exr_attr_chlist_t *chlist = NULL;
  if (st == SATF_OK && exr_get_channels(ctx, 0, &chlist) != EXR_ERR_SUCCESS)
    st = satf_error_set(err, SATF_ERR_FORMAT, "%s: no channel list", path);
  for (int i = 0; i < nnames && st == SATF_OK; i++) {
    int found = 0;
    for (int c = 0; c < chlist->num_channels; c++)
      if (strcmp(chlist->entries[c].name.str, names[i]) == 0)
        found = chlist->entries[c].x_sampling == 1 &&
                chlist->entries[c].y_sampling == 1;
    if (!found)
      st = satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: channel '%s' is missing or subsampled", path,
                          names[i]);
  }
  for (int i = 0; i < nnames && st == SATF_OK; i++) {
    planes[i] = malloc((size_t)(w * h) * sizeof(float));
    if (!planes[i])
      st = satf_error_set(err, SATF_ERR_NOMEM,
                          "%s: cannot allocate %lldx%lld pixels", path, w, h);
  }
  int32_t lines = 1;
  if (st == SATF_OK &&
      exr_get_scanlines_per_chunk(ctx, 0, &lines) != EXR_ERR_SUCCESS)
    st = satf_error_set(err, SATF_ERR_FORMAT, "%s: bad chunk layout", path);
  float *scratch = NULL;
  size_t scratch_size = 0;
  for (long long y = dw.min.y; st == SATF_OK && y <= dw.max.y; y += lines) {
    exr_chunk_info_t cinfo;
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    rc = exr_read_scanline_chunk_info(ctx, 0, (int)y, &cinfo);
    if (rc == EXR_ERR_SUCCESS)
      rc = exr_decoding_initialize(ctx, 0, &cinfo, &dec);
    if (rc == EXR_ERR_SUCCESS) {
      long long row0 = (long long)cinfo.start_y - dw.min.y;
      if (row0 < 0 || row0 + cinfo.height > h) {
        rc = EXR_ERR_CORRUPT_CHUNK;
      } else {
        /* Channels nobody asked for are decoded into scratch: OpenEXRCore
         * 3.1 can crash converting a chunk when some channels are skipped
         * (NULL decode_to_ptr) and others converted from half. */
        size_t need = (size_t)w * (size_t)cinfo.height;
        if (need > scratch_size) {
          float *grown = realloc(scratch, need * sizeof(float));
          if (grown) {
            scratch = grown;
            scratch_size = need;
          }
        }
        if (need > scratch_size)
          rc = EXR_ERR_OUT_OF_MEMORY;
        for (int e = 0; rc == EXR_ERR_SUCCESS && e < dec.channel_count; e++) {
          dec.channels[e].decode_to_ptr = (uint8_t *)scratch;
          for (int i = 0; i < nnames; i++)
            if (strcmp(names[i], dec.channels[e].channel_name) == 0)
              dec.channels[e].decode_to_ptr = (uint8_t *)(planes[i] + row0 * w);
          dec.channels[e].user_bytes_per_element = 4;
          dec.channels[e].user_data_type = EXR_PIXEL_FLOAT;
          dec.channels[e].user_pixel_stride = 4;
          dec.channels[e].user_line_stride = (int32_t)(4 * w);
        }
        if (rc == EXR_ERR_SUCCESS)
          rc = exr_decoding_choose_default_routines(ctx, 0, &dec);
        if (rc == EXR_ERR_SUCCESS)
          rc = exr_decoding_run(ctx, 0, &dec);
      }
    }
    exr_decoding_destroy(ctx, &dec);
    if (rc != EXR_ERR_SUCCESS)
      st = satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: cannot decode scanlines at y=%lld: %s", path, y,
                          describe(&msg, rc));
  }
  free(scratch);
  exr_finish(&ctx);
  if (st != SATF_OK) {
    for (int i = 0; i < nnames; i++) {
      free(planes[i]);
      planes[i] = NULL;
    }
    return st;
  }
  *width_out = (int)w;
  *height_out = (int)h;
  return SATF_OK;
}
