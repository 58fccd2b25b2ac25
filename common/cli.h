/* cli.h - strict parsing of command-line numbers. Each parser rejects empty
 * strings, trailing garbage, NaN/inf and values outside [lo, hi], and prints
 * "PROG: --flag: ..." to stderr so every tool words its errors the same. */
#ifndef SATF_COMMON_CLI_H
#define SATF_COMMON_CLI_H

#include <stdint.h>

int satf_cli_int(const char *prog, const char *flag, const char *text, long lo,
                 long hi, long *out);
int satf_cli_u64(const char *prog, const char *flag, const char *text,
                 uint64_t *out);
int satf_cli_double(const char *prog, const char *flag, const char *text,
                    double lo, double hi, double *out);
/* Parses "WxH" with both sides in [lo, hi]. */
int satf_cli_size(const char *prog, const char *flag, const char *text, long lo,
                  long hi, long *w, long *h);

#endif
