/* exr_layout.c - satf_exr_check_layout (satf/common.h): the byte layout
 * of a single-part scanline EXR as this project writes it, beyond what a
 * reader needs to get the pixels back. */
#define _XOPEN_SOURCE 700 /* pread */
#include "satf/common.h"

#include <errno.h>
#include <fcntl.h>
#include <openexr.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static uint64_t le64(const unsigned char *b) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; i--)
    v = v << 8 | b[i];
  return v;
}

/* Compares the offset table with where each chunk really starts (OpenEXR
 * rebuilds a damaged table when it reads, so a zeroed one still gives the
 * pixels), checks that the chunks follow each other with nothing between
 * and nothing after the last, and that the line order is increasing. */
static satf_status check_chunks(const char *path, exr_const_context_t ctx,
                                int fd, long long fsize, satf_error *err) {
  exr_lineorder_t order;
  if (exr_get_lineorder(ctx, 0, &order) != EXR_ERR_SUCCESS ||
      order != EXR_LINEORDER_INCREASING_Y)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: the line order is not increasing", path);
  int32_t count = 0, lines = 0;
  exr_attr_box2i_t dw;
  if (exr_get_chunk_count(ctx, 0, &count) != EXR_ERR_SUCCESS || count < 1 ||
      exr_get_scanlines_per_chunk(ctx, 0, &lines) != EXR_ERR_SUCCESS ||
      lines < 1 || exr_get_data_window(ctx, 0, &dw) != EXR_ERR_SUCCESS)
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: no chunks", path);
  unsigned char entry[8];
  uint64_t table = 0, expect = 0;
  for (int32_t i = 0; i < count; i++) {
    exr_chunk_info_t c;
    if (exr_read_scanline_chunk_info(ctx, 0, dw.min.y + i * lines, &c) !=
        EXR_ERR_SUCCESS)
      return satf_error_set(err, SATF_ERR_CORRUPT, "%s: chunk %d is damaged",
                            path, i);
    uint64_t start = c.data_offset - 8; /* y and size precede the data */
    if (i == 0) {
      if (c.data_offset < 8 + 8 * (uint64_t)count)
        return satf_error_set(err, SATF_ERR_CORRUPT,
                              "%s: no room for the offset table", path);
      table = start - 8 * (uint64_t)count;
    } else if (start != expect) {
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: chunk %d starts at byte %llu, not right "
                            "after chunk %d (byte %llu)",
                            path, i, (unsigned long long)start, i - 1,
                            (unsigned long long)expect);
    }
    if (pread(fd, entry, 8, (off_t)(table + 8 * (uint64_t)i)) != 8)
      return satf_error_set(err, SATF_ERR_IO, "%s: cannot read: %s", path,
                            strerror(errno));
    if (le64(entry) != start)
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: offset table entry %d says byte %llu, the "
                            "chunk is at byte %llu",
                            path, i, (unsigned long long)le64(entry),
                            (unsigned long long)start);
    expect = c.data_offset + c.packed_size;
  }
  if (expect != (uint64_t)fsize)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: %lld bytes follow the last chunk", path,
                          (long long)fsize - (long long)expect);
  return SATF_OK;
}

static void quiet(exr_const_context_t ctx, exr_result_t code, const char *msg) {
  (void)ctx, (void)code, (void)msg; /* the caller reports what failed */
}

satf_status satf_exr_check_layout(const char *path, satf_error *err) {
  int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  struct stat st;
  if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    int e = errno;
    if (fd >= 0)
      close(fd);
    return fd < 0 ? satf_error_set(err, SATF_ERR_IO, "%s: cannot open: %s",
                                   path, strerror(e))
                  : satf_error_set(err, SATF_ERR_IO, "%s: not a regular file",
                                   path);
  }
  exr_context_t ctx = NULL;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = quiet;
  satf_status s = SATF_OK;
  int parts = 0;
  exr_storage_t storage = EXR_STORAGE_LAST_TYPE;
  if (exr_start_read(&ctx, path, &init) != EXR_ERR_SUCCESS ||
      exr_get_count(ctx, &parts) != EXR_ERR_SUCCESS || parts != 1 ||
      exr_get_storage(ctx, 0, &storage) != EXR_ERR_SUCCESS ||
      storage != EXR_STORAGE_SCANLINE)
    s = satf_error_set(err, SATF_ERR_FORMAT,
                       "%s: not a single-part scanline OpenEXR file", path);
  else
    s = check_chunks(path, ctx, fd, (long long)st.st_size, err);
  exr_finish(&ctx);
  close(fd);
  return s;
}
