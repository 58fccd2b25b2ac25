/* error.c - satf_error formatting. */
#include "satf/satf.h"

#include <stdarg.h>
#include <stdio.h>

const char *satf_status_name(satf_status status) {
  switch (status) {
  case SATF_OK: return "ok";
  case SATF_ERR_ARGUMENT: return "invalid argument";
  case SATF_ERR_NOMEM: return "out of memory";
  case SATF_ERR_IO: return "i/o error";
  case SATF_ERR_FORMAT: return "wrong format";
  case SATF_ERR_CORRUPT: return "corrupt data";
  case SATF_ERR_VERSION: return "unsupported version";
  case SATF_ERR_INCOMPATIBLE: return "incompatible parameters";
  case SATF_ERR_GL: return "graphics error";
  case SATF_ERR_INTERNAL: return "internal error";
  }
  return "unknown status";
}

satf_status satf_error_set(satf_error *err, satf_status status, const char *fmt,
                           ...) {
  if (err) {
    va_list ap;
    va_start(ap, fmt);
    err->status = status;
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
  }
  return status;
}

void satf_error_clear(satf_error *err) {
  if (err) {
    err->status = SATF_OK;
    err->message[0] = '\0';
  }
}
