/* cli.c - the argument loop and number parsers declared in satf/common.h.
 * All return 0 on success, -1 after printing (satf_cli_unknown: 2). */
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
  /* strtoull accepts "-4" (even after blanks) and wraps it around */
  size_t blanks = text ? strspn(text, " \t\n\v\f\r") : 0;
  if (!text || !*text || text[blanks] == '-') {
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

void satf_cli_begin(satf_cli_args *it, const char *prog, int argc,
                    char *const *argv) {
  memset(it, 0, sizeof *it);
  it->prog = prog;
  it->argc = argc;
  it->argv = argv;
  it->next = 1;
  it->hint = " (see --help)";
}

int satf_cli_next(satf_cli_args *it) {
  it->arg = NULL;
  it->closest = NULL;
  it->closest_distance = 1 << 30;
  if (it->next >= it->argc)
    return 0;
  it->arg = it->argv[it->next++];
  if (it->dashdash && !it->only_positional && !strcmp(it->arg, "--")) {
    it->only_positional = 1;
    return satf_cli_next(it);
  }
  return 1;
}

int satf_cli_edit_distance(const char *a, const char *b) {
  enum { N = 64 };
  int row[N], la = 0, lb = 0;
  while (la < N - 1 && a[la])
    la++;
  while (lb < N - 1 && b[lb])
    lb++;
  for (int j = 0; j <= lb; j++)
    row[j] = j;
  for (int i = 1; i <= la; i++) {
    int diag = row[0];
    row[0] = i;
    for (int j = 1; j <= lb; j++) {
      int up = row[j];
      int best = diag + (a[i - 1] != b[j - 1]);
      if (up + 1 < best)
        best = up + 1;
      if (row[j - 1] + 1 < best)
        best = row[j - 1] + 1;
      row[j] = best;
      diag = up;
    }
  }
  return row[lb];
}

int satf_cli_is(satf_cli_args *it, const char *short_name,
                const char *long_name) {
  if (!it->arg || it->only_positional)
    return 0;
  if ((short_name && !strcmp(it->arg, short_name)) ||
      (long_name && !strcmp(it->arg, long_name)))
    return 1;
  if (long_name && it->arg[0] == '-') {
    int d = satf_cli_edit_distance(it->arg, long_name);
    if (d < it->closest_distance) {
      it->closest = long_name;
      it->closest_distance = d;
    }
  }
  return 0;
}

int satf_cli_positional(const satf_cli_args *it) {
  return it->arg && (it->only_positional || it->arg[0] != '-');
}

int satf_cli_value(satf_cli_args *it, const char **value) {
  if (it->next >= it->argc) {
    fprintf(stderr, "%s: %s needs a value%s\n", it->prog, it->arg, it->hint);
    return -1;
  }
  *value = it->argv[it->next++];
  return 0;
}

int satf_cli_value_int(satf_cli_args *it, long lo, long hi, long *out) {
  const char *v;
  return satf_cli_value(it, &v)
             ? -1
             : satf_cli_int(it->prog, it->arg, v, lo, hi, out);
}

int satf_cli_value_u64(satf_cli_args *it, uint64_t *out) {
  const char *v;
  return satf_cli_value(it, &v) ? -1 : satf_cli_u64(it->prog, it->arg, v, out);
}

int satf_cli_value_double(satf_cli_args *it, double lo, double hi,
                          double *out) {
  const char *v;
  return satf_cli_value(it, &v)
             ? -1
             : satf_cli_double(it->prog, it->arg, v, lo, hi, out);
}

int satf_cli_value_size(satf_cli_args *it, long lo, long hi, long *w, long *h) {
  const char *v;
  return satf_cli_value(it, &v)
             ? -1
             : satf_cli_size(it->prog, it->arg, v, lo, hi, w, h);
}

int satf_cli_unknown(const satf_cli_args *it) {
  /* a suggestion only when it is plausibly a slip: at most two edits, and
   * fewer than a third of the option's length */
  int len = it->closest ? (int)strlen(it->closest) : 0;
  if (it->closest && it->closest_distance <= 2 &&
      3 * it->closest_distance < len)
    fprintf(stderr, "%s: unknown option '%s' (did you mean '%s'?)%s\n",
            it->prog, it->arg, it->closest, it->hint);
  else
    fprintf(stderr, "%s: unknown option '%s'%s\n", it->prog, it->arg, it->hint);
  return 2;
}
