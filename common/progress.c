/* progress.c - see progress.h. */
#define _POSIX_C_SOURCE 200809L
#include "satf/common.h"

#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

double satf_now_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double satf_peak_memory_mb(void) {
  struct rusage ru;
  return getrusage(RUSAGE_SELF, &ru) == 0 ? (double)ru.ru_maxrss / 1024.0 : 0.0;
}

void satf_progress_begin(satf_progress *p, FILE *out, const char *label,
                         const char *unit, size_t units_per_item, int quiet) {
  p->out = out;
  p->label = label;
  p->unit = unit;
  p->units_per_item = units_per_item ? units_per_item : 1;
  p->is_tty = isatty(fileno(out));
  p->quiet = quiet;
  p->start = satf_now_seconds();
  p->last_print = p->start;
}

static void format_eta(double seconds, char *buf, size_t size) {
  if (seconds < 0 || seconds > 360000) {
    snprintf(buf, size, "--:--");
    return;
  }
  int s = (int)(seconds + 0.5);
  if (s >= 3600)
    snprintf(buf, size, "%d:%02d:%02d", s / 3600, s / 60 % 60, s % 60);
  else
    snprintf(buf, size, "%02d:%02d", s / 60, s % 60);
}

void satf_progress_update(satf_progress *p, size_t done, size_t total) {
  if (p->quiet || total == 0)
    return;
  double now = satf_now_seconds();
  double interval = p->is_tty ? 0.1 : 5.0;
  if (done < total && now - p->last_print < interval)
    return;
  p->last_print = now;
  double elapsed = now - p->start;
  double frac = (double)done / (double)total;
  double rate =
      elapsed > 0 ? (double)done * (double)p->units_per_item / elapsed : 0.0;
  char eta[32];
  format_eta(done > 0 ? elapsed * (1.0 - frac) / frac : -1.0, eta, sizeof eta);
  if (p->is_tty) {
    char bar[31];
    int filled = (int)(frac * 30.0);
    for (int i = 0; i < 30; i++)
      bar[i] = i < filled ? '#' : '.';
    bar[30] = '\0';
    fprintf(p->out, "\r%s [%s] %5.1f%%  %.0f %s/s  ETA %s ", p->label, bar,
            100.0 * frac, rate, p->unit, eta);
  } else {
    fprintf(p->out, "%s: %zu/%zu (%.1f%%), %.0f %s/s, ETA %s\n", p->label, done,
            total, 100.0 * frac, rate, p->unit, eta);
  }
  fflush(p->out);
}

void satf_progress_end(satf_progress *p) {
  if (!p->quiet && p->is_tty) {
    fputc('\n', p->out);
    fflush(p->out);
  }
}

const char *satf_format_bytes(double bytes, char *buf, size_t size) {
  const char *units[] = {"B", "KB", "MB", "GB", "TB"};
  int u = 0;
  while (bytes >= 1000.0 && u < 4) {
    bytes /= 1000.0;
    u++;
  }
  snprintf(buf, size, u == 0 ? "%.0f %s" : "%.1f %s", bytes, units[u]);
  return buf;
}
