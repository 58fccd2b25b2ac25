/* progress.h - progress reporting on stderr: a redrawn bar (percent, rate,
 * ETA) when stderr is a terminal, a plain line every few seconds otherwise,
 * so logs from CI and pipes stay readable. */
#ifndef SATF_COMMON_PROGRESS_H
#define SATF_COMMON_PROGRESS_H

#include <stddef.h>
#include <stdio.h>

typedef struct satf_progress {
  FILE *out;
  const char *label;     /* e.g. "building" */
  const char *unit;      /* e.g. "HRIRs" */
  size_t units_per_item; /* rate is reported in units: items x this */
  int is_tty;
  int quiet;
  double start;      /* seconds, monotonic */
  double last_print; /* seconds, monotonic */
} satf_progress;

double satf_now_seconds(void);

void satf_progress_begin(satf_progress *p, FILE *out, const char *label,
                         const char *unit, size_t units_per_item, int quiet);
void satf_progress_update(satf_progress *p, size_t done, size_t total);
/* Finishes the bar line (terminal) so following output starts cleanly. */
void satf_progress_end(satf_progress *p);

/* Formats a byte count as "12.3 MB" into buf. */
const char *satf_format_bytes(double bytes, char *buf, size_t size);

#endif
