/* common.h - the foundation library (common/): strict command-line number
 * parsing, crash-safe file output and capped file reading, a parallel-for,
 * progress bars, deterministic random numbers and the one place satf reads
 * and writes OpenEXR (through OpenEXRCore). Every other library builds on it;
 * it depends on nothing of satf's but satf.h (status and errors). */
#ifndef SATF_COMMON_H
#define SATF_COMMON_H

#include <openexr.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "satf/satf.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Command lines ----
 * the command-line argument loop every tool shares, and strict
 * parsing of command-line numbers. Each parser rejects empty strings,
 * trailing garbage, NaN/inf and values outside [lo, hi], and prints
 * "PROG: --flag: ..." to stderr so every tool words its errors the same.
 * All functions returning int return 0 on success and -1 after printing,
 * except satf_cli_unknown, which returns the usage exit status 2.
 *
 * The loop:
 *
 *   satf_cli_args it;
 *   satf_cli_begin(&it, PROG, argc, argv);
 *   while (satf_cli_next(&it)) {
 *     if (satf_cli_is(&it, "-h", "--help")) {
 *       usage(stdout);
 *       return 0;
 *     } else if (satf_cli_is(&it, "-o", "--output")) {
 *       if (satf_cli_value(&it, &out))      // "PROG: -o needs a value
 *         return 2;                         //  (see --help)"
 *     } else if (satf_cli_is(&it, NULL, "--samples")) {
 *       if (satf_cli_value_int(&it, 1, 1000000, &samples))
 *         return 2;
 *     } else if (satf_cli_positional(&it)) {
 *       input = it.arg;
 *     } else {
 *       return satf_cli_unknown(&it);       // "PROG: unknown option 'X'
 *     }                                     //  (see --help)", returns 2
 *   }
 *
 * Messages name the flag as the user spelled it (it.arg). */

typedef struct satf_cli_args {
  const char *prog;    /* "PROG" of every message */
  int argc;            /* argv[0] is the program and is skipped */
  char *const *argv;   /* argv[argc] need not exist */
  int next;            /* index of the next argument; set it to start later */
  const char *arg;     /* the current argument, after satf_cli_next */
  const char *hint;    /* ends the messages; " (see --help)" by default */
  int dashdash;        /* 0 by default: "--" is an ordinary (unknown) option;
                          1: "--" is skipped and every later argument is
                          positional */
  int only_positional; /* a "--" was seen (with dashdash) */
  /* The option satf_cli_is was asked about that is nearest the current
   * argument by edit distance (for "did you mean"), and that distance. */
  const char *closest;
  int closest_distance;
} satf_cli_args;

void satf_cli_begin(satf_cli_args *it, const char *prog, int argc,
                    char *const *argv);
/* Moves to the next argument (it->arg); returns 0 when there is none. */
int satf_cli_next(satf_cli_args *it);
/* Whether the current argument is the option short_name or long_name (either
 * may be NULL). Never true after "--". */
int satf_cli_is(satf_cli_args *it, const char *short_name,
                const char *long_name);
/* Whether the current argument is not an option: it does not start with '-'
 * (a lone "-" counts as an option), or it follows "--". */
int satf_cli_positional(const satf_cli_args *it);
/* Takes the argument after the current option as its value, whatever it
 * looks like; prints "PROG: FLAG needs a value HINT" if there is none. */
int satf_cli_value(satf_cli_args *it, const char **value);
/* satf_cli_value, then the matching parser below with it->arg as the flag. */
int satf_cli_value_int(satf_cli_args *it, long lo, long hi, long *out);
int satf_cli_value_u64(satf_cli_args *it, uint64_t *out);
int satf_cli_value_double(satf_cli_args *it, double lo, double hi, double *out);
int satf_cli_value_size(satf_cli_args *it, long lo, long hi, long *w, long *h);
/* Prints "PROG: unknown option 'ARG' HINT" and returns 2. */
int satf_cli_unknown(const satf_cli_args *it);
/* Levenshtein edit distance between a and b (each read up to 63 bytes). */
int satf_cli_edit_distance(const char *a, const char *b);

int satf_cli_int(const char *prog, const char *flag, const char *text, long lo,
                 long hi, long *out);
int satf_cli_u64(const char *prog, const char *flag, const char *text,
                 uint64_t *out);
int satf_cli_double(const char *prog, const char *flag, const char *text,
                    double lo, double hi, double *out);
/* Parses "WxH" with both sides in [lo, hi]. */
int satf_cli_size(const char *prog, const char *flag, const char *text, long lo,
                  long hi, long *w, long *h);

/* ---- Files ----
 * crash-safe output: write to "PATH.tmp-PID" next to the target,
 * then rename into place, so a killed process never leaves a half-written
 * file under the final name. */

/* Fills tmp with a temporary path in the same directory as path
 * ("PATH.tmp-PID"), first removing the PATH.tmp-* files of processes that
 * no longer run (left by a kill before their rename). */
satf_status satf_temp_path(const char *path, char *tmp, size_t size,
                           satf_error *err);
/* fsyncs tmp and renames it to path; removes tmp on failure. */
satf_status satf_commit_temp(const char *tmp, const char *path,
                             satf_error *err);
/* Writes size bytes to path through a temporary file renamed into place. */
satf_status satf_write_file_atomic(const char *path, const void *data,
                                   size_t size, satf_error *err);
/* Size of a file in bytes, or -1. */
long long satf_file_size(const char *path);

/* Reads the whole regular file at path into *data (malloc'd, caller frees;
 * one NUL byte follows the *size bytes, so text can be used as a string).
 * The size is checked against max_bytes before anything is allocated, and a
 * file that grows or shrinks while it is read is an error, never a silently
 * truncated result. On failure *data is NULL, *size is 0 and err holds one
 * of (SATF_ERR_IO unless noted):
 *   "PATH: cannot open: REASON"          (missing, no permission, ...)
 *   "PATH: not a regular file"           (a directory, a FIFO, a device)
 *   "PATH: N bytes is over the limit of MAX bytes"
 *   "PATH: cannot hold N bytes"          (SATF_ERR_NOMEM)
 *   "PATH: read failed: REASON"
 *   "PATH: changed size while being read" */
satf_status satf_read_file(const char *path, size_t max_bytes, void **data,
                           size_t *size, satf_error *err);

/* ---- Installed data (data_dir.c) ---------------------------------------- */

/* The folder the installed tools keep their data in: $SATF_DATA_DIR when
 * set, else PREFIX/share/satf for a program installed as PREFIX/bin/NAME
 * (where `cmake --install` and `satf-build --install-default` put the
 * default databases). Writes it to out; -1 when it cannot be known or does
 * not fit. */
int satf_data_dir(char *out, size_t size);

/* The installed default database: satf_data_dir()/satf-default.hrirdb.exr
 * (Phong records) or, with fiber, satf-fiber.hrirdb.exr. Its path is
 * written to out and returned when it is a regular file; else NULL. */
const char *satf_default_database(int fiber, char *out, size_t size);

/* One file named on a command line: what it is ("the scene", "-o") and
 * whether the program writes it. */
typedef struct satf_file_role {
  const char *what;
  const char *path; /* NULL: not given, skipped */
  int is_output;
} satf_file_role;

/* 1 when path ends in ext (".exr"; ASCII case ignored) after a non-empty
 * file name. */
int satf_path_has_extension(const char *path, const char *ext);

/* Refuses (SATF_ERR_ARGUMENT) an output whose name says another format
 * than the one written: "WHAT PATH: writes KIND; name it *EXT". NULL path:
 * nothing to check. */
satf_status satf_check_output_extension(const char *what, const char *path,
                                        const char *ext, const char *kind,
                                        satf_error *err);

/* Refuses (SATF_ERR_ARGUMENT, "OUTPUT-WHAT PATH is the same file as
 * OTHER-WHAT PATH") when an output names the same file as an input or as
 * another output, however it is spelt: existing files compare by device
 * and inode (symbolic links followed, hard links caught), files still to
 * be written by their resolved directory and name. Outputs are written
 * through a temporary file renamed into place, so without this check the
 * rename would silently replace the input. */
satf_status satf_check_distinct_files(const satf_file_role *files, int n,
                                      satf_error *err);

/* ---- Parallel-for ----
 * a minimal parallel-for over pthreads. Work items are claimed
 * from an atomic counter, so the result of each item must not depend on
 * which thread ran it. */

/* Called for item i on some thread; `thread` is in [0, threads). Returns 0 on
 * success; a non-zero return stops further items from being claimed and is
 * returned by satf_parallel_for (the first failure wins). */
typedef int (*satf_parallel_fn)(void *ctx, size_t i, int thread);

/* Called about every 100 ms on the calling thread with the number of items
 * finished so far (may be NULL). */
typedef void (*satf_progress_fn)(void *ctx, size_t done, size_t total);

/* Runs fn for every i in [0, count) on `threads` threads (0 = all cores). */
int satf_parallel_for(size_t count, int threads, satf_parallel_fn fn, void *ctx,
                      satf_progress_fn progress, void *progress_ctx);

/* Number of online processors (at least 1). */
int satf_cpu_count(void);

/* Whether the processor converts halfs in hardware: AVX (with the system's
 * support for its registers) and F16C; with avx2 also AVX2. 0 off x86. */
int satf_cpu_has_f16c(int avx2);

/* ---- Progress ----
 * progress reporting on stderr: a redrawn bar (percent, rate,
 * ETA) when stderr is a terminal, a plain line every few seconds otherwise,
 * so logs from CI and pipes stay readable. */

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
/* The process's peak resident memory so far, in MB (0 where the system
 * does not say). */
double satf_peak_memory_mb(void);

void satf_progress_begin(satf_progress *p, FILE *out, const char *label,
                         const char *unit, size_t units_per_item, int quiet);
void satf_progress_update(satf_progress *p, size_t done, size_t total);
/* Finishes the bar line (terminal) so following output starts cleanly. */
void satf_progress_end(satf_progress *p);

/* Formats a byte count as "12.3 MB" into buf. */
const char *satf_format_bytes(double bytes, char *buf, size_t size);

/* ---- Random numbers ----
 * small deterministic random numbers (splitmix64 seeding, xoshiro128+
 * style generation is not needed: splitmix64 alone is fast and passes
 * BigCrush for our use). Stream i of seed s is independent of thread count,
 * which is what makes database builds bit-identical across --threads. */

typedef struct satf_rng {
  uint64_t state;
} satf_rng;

/* Seeds stream `stream` of master seed `seed`. */
void satf_rng_seed(satf_rng *rng, uint64_t seed, uint64_t stream);
uint64_t satf_rng_u64(satf_rng *rng);
/* Uniform in [0, 1) with 53 random bits. */
double satf_rng_uniform(satf_rng *rng);
/* Uniform in [lo, hi). */
double satf_rng_range(satf_rng *rng, double lo, double hi);
/* Uniform integer in [0, n), n > 0. */
uint32_t satf_rng_below(satf_rng *rng, uint32_t n);
/* Standard normal (Box-Muller, one value per call). */
double satf_rng_normal(satf_rng *rng);

/* ---- OpenEXR ----
 * the one place satf reads and writes OpenEXR files, through
 * OpenEXRCore: single-part scanline images of planar float channels, plus a
 * callback for custom header attributes. Used by the HRIR database (whose
 * container is an EXR image) and by the renderer's frame output. */

typedef struct satf_exr_channel {
  const char *name;
  const float *data; /* width x height, row-major, top row first */
} satf_exr_channel;

/* Adds custom attributes to the part before the header is written. */
typedef satf_status (*satf_exr_attr_writer)(void *ctx, exr_context_t exr,
                                            int part, satf_error *err);
/* Inspects the header after it is read and before any pixel is allocated;
 * returning non-OK aborts the read with that error. */
typedef satf_status (*satf_exr_attr_reader)(void *ctx, exr_const_context_t exr,
                                            int part, int width, int height,
                                            satf_error *err);

typedef struct satf_exr_write_opts {
  exr_pixel_type_t pixel_type;   /* EXR_PIXEL_HALF or EXR_PIXEL_FLOAT */
  exr_compression_t compression; /* e.g. EXR_COMPRESSION_ZIP */
  satf_exr_attr_writer attrs;    /* may be NULL */
  void *attrs_ctx;
  int threads; /* chunks compressed on this many threads; 0: every core */
} satf_exr_write_opts;

/* Writes through a temporary file renamed into place. */
satf_status satf_exr_write(const char *path, int width, int height,
                           const satf_exr_channel *channels, int nchannels,
                           const satf_exr_write_opts *opts, satf_error *err);
/* The same with each channel's pixel type given (types[c]) in place of
 * the options' one: a FLOAT depth beside HALF colour. */
satf_status satf_exr_write_typed(const char *path, int width, int height,
                                 const satf_exr_channel *channels,
                                 const exr_pixel_type_t *types, int nchannels,
                                 const satf_exr_write_opts *opts,
                                 satf_error *err);

/* Reads the named channels of a single-part scanline file into planes[i]
 * (malloc'd, width*height floats each, caller frees). A channel missing
 * from the file is an error. max_pixels bounds width*height. */
satf_status satf_exr_read(const char *path, const char *const *names,
                          int nnames, long long max_pixels,
                          satf_exr_attr_reader attrs, void *attrs_ctx,
                          int *width, int *height, float **planes,
                          satf_error *err);

/* Checks what a reader does not need to get the pixels back yet a file
 * written by satf_exr_write always has: an offset table that names where
 * each chunk starts (readers rebuild a damaged one), chunks one after the
 * other in increasing line order, and nothing after the last.
 * SATF_ERR_CORRUPT names the first difference. */
satf_status satf_exr_check_layout(const char *path, satf_error *err);

#ifdef __cplusplus
}
#endif
#endif
