/* strands_read.h - reading a whole strand file (capped at
 * SATF_STRANDS_MAX_FILE_BYTES, regular files only) and handing its bytes to
 * one format's parser: what every satf_*_read of the import library does. */
#ifndef SATF_IMPORT_STRANDS_READ_H
#define SATF_IMPORT_STRANDS_READ_H

#include <stdlib.h>

#include "satf/common.h"
#include "satf/import.h"

typedef satf_status (*strands_parse_fn)(const void *data, size_t size,
                                        const char *name, satf_strand_set **out,
                                        satf_error *err);

static inline satf_status strands_read_file(const char *path,
                                            strands_parse_fn parse,
                                            satf_strand_set **out,
                                            satf_error *err) {
  *out = NULL;
  void *data;
  size_t size;
  satf_status st =
      satf_read_file(path, SATF_STRANDS_MAX_FILE_BYTES, &data, &size, err);
  if (st == SATF_OK)
    st = parse(data, size, path, out, err);
  free(data);
  return st;
}

#endif
