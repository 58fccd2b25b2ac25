/* cli.c - see cli.h. All parsers return 0 on success, -1 after printing. */
#include "satf/common.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int satf_cli_int(const char *prog, const char *flag, const char *text, long lo,
                 long hi, long *out) {
  char *end = NULL;
  errno = 0;
  long v = text ? strtol(text, &end, 10) : 0;
  if (!text || !*text || *end != '\0' || errno == ERANGE) {
    fprintf(stderr, "%s: %s: expected an integer, got '%s'\n", prog, flag,
            text ? text : "");
    return -1;
  }
  if (v < lo || v > hi) {
    fprintf(stderr, "%s: %s: %ld is out of range [%ld, %ld]\n", prog, flag, v,
            lo, hi);
    return -1;
  }
  *out = v;
  return 0;
}

int satf_cli_u64(const char *prog, const char *flag, const char *text,
                 uint64_t *out) {
  char *end = NULL;
  errno = 0;
  if (!text || !*text || text[0] == '-') {
    fprintf(stderr, "%s: %s: expected a non-negative integer, got '%s'\n", prog,
            flag, text ? text : "");
    return -1;
  }
  unsigned long long v = strtoull(text, &end, 0);
  if (*end != '\0' || errno == ERANGE) {
    fprintf(stderr, "%s: %s: expected a non-negative integer, got '%s'\n", prog,
            flag, text);
    return -1;
  }
  *out = (uint64_t)v;
  return 0;
}

int satf_cli_double(const char *prog, const char *flag, const char *text,
                    double lo, double hi, double *out) {
  char *end = NULL;
  errno = 0;
  double v = text ? strtod(text, &end) : 0;
  if (!text || !*text || *end != '\0' || errno == ERANGE || !isfinite(v)) {
    fprintf(stderr, "%s: %s: expected a finite number, got '%s'\n", prog, flag,
            text ? text : "");
    return -1;
  }
  if (v < lo || v > hi) {
    fprintf(stderr, "%s: %s: %g is out of range [%g, %g]\n", prog, flag, v, lo,
            hi);
    return -1;
  }
  *out = v;
  return 0;
}

int satf_cli_size(const char *prog, const char *flag, const char *text, long lo,
                  long hi, long *w, long *h) {
  const char *x = text ? strchr(text, 'x') : NULL;
  if (!x) {
    fprintf(stderr, "%s: %s: expected WIDTHxHEIGHT, got '%s'\n", prog, flag,
            text ? text : "");
    return -1;
  }
  char left[32];
  size_t n = (size_t)(x - text);
  if (n == 0 || n >= sizeof left) {
    fprintf(stderr, "%s: %s: expected WIDTHxHEIGHT, got '%s'\n", prog, flag,
            text);
    return -1;
  }
  memcpy(left, text, n);
  left[n] = '\0';
  if (satf_cli_int(prog, flag, left, lo, hi, w) != 0 ||
      satf_cli_int(prog, flag, x + 1, lo, hi, h) != 0)
    return -1;
  return 0;
}
