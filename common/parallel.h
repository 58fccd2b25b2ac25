/* parallel.h - a minimal parallel-for over pthreads. Work items are claimed
 * from an atomic counter, so the result of each item must not depend on
 * which thread ran it. */
#ifndef SATF_COMMON_PARALLEL_H
#define SATF_COMMON_PARALLEL_H

#include <stddef.h>

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

#endif
