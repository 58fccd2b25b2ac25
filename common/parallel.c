/* parallel.c - see parallel.h. */
#define _POSIX_C_SOURCE 200809L
#include "satf/common.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>
#if (defined(__GNUC__) || defined(__clang__)) &&                               \
    (defined(__x86_64__) || defined(__i386__))
#include <cpuid.h>
#endif

typedef struct pool {
  satf_parallel_fn fn;
  void *ctx;
  size_t count;
  atomic_size_t next;
  atomic_size_t done;
  atomic_int failure;
} pool;

typedef struct worker {
  pool *p;
  int index;
} worker;

static void *worker_main(void *arg) {
  worker *w = arg;
  pool *p = w->p;
  for (;;) {
    if (atomic_load(&p->failure) != 0)
      break;
    size_t i = atomic_fetch_add(&p->next, 1);
    if (i >= p->count)
      break;
    int rc = p->fn(p->ctx, i, w->index);
    if (rc != 0) {
      int expected = 0;
      atomic_compare_exchange_strong(&p->failure, &expected, rc);
      break;
    }
    atomic_fetch_add(&p->done, 1);
  }
  return NULL;
}

int satf_cpu_has_f16c(int avx2) {
#if (defined(__GNUC__) || defined(__clang__)) &&                               \
    (defined(__x86_64__) || defined(__i386__))
  /* Asked once a process and remembered: the maps ask at every half
   * conversion, and CPUID, which a virtual machine's hypervisor answers,
   * cost 0.5% of the shared ponytail's frames (perf). -1: not asked yet. */
  static _Atomic int known[2] = {-1, -1};
  int has = atomic_load(&known[avx2 != 0]);
  if (has >= 0)
    return has;
  /* clang 14's __builtin_cpu_supports knows no "f16c": CPUID leaf 1 has it
   * (ECX bit 29); the builtin checks AVX and AVX2 with the system's support */
  unsigned a, b, c, d;
  has = __get_cpuid(1, &a, &b, &c, &d) && (c & bit_F16C) &&
        (avx2 ? __builtin_cpu_supports("avx2") : __builtin_cpu_supports("avx"));
  atomic_store(&known[avx2 != 0], has);
  return has;
#else
  (void)avx2;
  return 0;
#endif
}

int satf_cpu_count(void) {
  long n = sysconf(_SC_NPROCESSORS_ONLN);
  return n < 1 ? 1 : (int)n;
}

int satf_parallel_for(size_t count, int threads, satf_parallel_fn fn, void *ctx,
                      satf_progress_fn progress, void *progress_ctx) {
  if (threads <= 0)
    threads = satf_cpu_count();
  if ((size_t)threads > count)
    threads = count == 0 ? 1 : (int)count;
  pool p = {.fn = fn, .ctx = ctx, .count = count};
  atomic_init(&p.next, 0);
  atomic_init(&p.done, 0);
  atomic_init(&p.failure, 0);

  /* The caller's thread is worker 0 unless it must report progress, in
   * which case all workers are spawned and the caller only watches. */
  int spawn = progress ? threads : threads - 1;
  pthread_t *tids = calloc((size_t)(spawn > 0 ? spawn : 1), sizeof *tids);
  worker *ws = calloc((size_t)threads, sizeof *ws);
  if (!tids || !ws) {
    free(tids);
    free(ws);
    return -1;
  }
  int started = 0;
  for (int t = 0; t < threads; t++) {
    ws[t].p = &p;
    ws[t].index = t;
  }
  int first = progress ? 0 : 1;
  for (int t = first; t < threads; t++) {
    if (pthread_create(&tids[started], NULL, worker_main, &ws[t]) != 0)
      break;
    started++;
  }
  if (!progress) {
    worker_main(&ws[0]);
  } else {
    if (started == 0) /* could not spawn: do the work here */
      worker_main(&ws[0]);
    while (atomic_load(&p.done) < count && atomic_load(&p.failure) == 0 &&
           started > 0) {
      progress(progress_ctx, atomic_load(&p.done), count);
      struct timespec ts = {0, 100 * 1000 * 1000};
      nanosleep(&ts, NULL);
    }
  }
  for (int t = 0; t < started; t++)
    pthread_join(tids[t], NULL);
  if (progress)
    progress(progress_ctx, atomic_load(&p.done), count);
  free(tids);
  free(ws);
  return atomic_load(&p.failure);
}
