/* satf.h - status codes and error reporting shared by every satf module.
 *
 * Every fallible call returns a satf_status and, when given a non-NULL
 * satf_error, fills it with a readable message naming what went wrong.
 * There is no global error state: the caller owns the satf_error. */
#ifndef SATF_SATF_H
#define SATF_SATF_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SATF_VERSION_STRING "0.1.0"

typedef enum satf_status {
  SATF_OK = 0,
  SATF_ERR_ARGUMENT,     /* a parameter is out of range or malformed */
  SATF_ERR_NOMEM,        /* an allocation failed or would be absurd */
  SATF_ERR_IO,           /* a file could not be opened, read or written */
  SATF_ERR_FORMAT,       /* a file is not of the expected kind */
  SATF_ERR_CORRUPT,      /* a file is of the right kind but damaged */
  SATF_ERR_VERSION,      /* a file was written by an incompatible version */
  SATF_ERR_INCOMPATIBLE, /* a file was built with incompatible parameters */
  SATF_ERR_GL,           /* the graphics context or a shader failed */
  SATF_ERR_INTERNAL
} satf_status;

typedef struct satf_error {
  satf_status status;
  char message[768];
} satf_error;

const char *satf_status_name(satf_status status);

/* Records status and a printf-style message in err (if non-NULL) and returns
 * status, so callers can write `return satf_error_set(err, ...)`. */
satf_status satf_error_set(satf_error *err, satf_status status, const char *fmt,
                           ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Clears err to SATF_OK with an empty message. */
void satf_error_clear(satf_error *err);

#ifdef __cplusplus
}
#endif
#endif
