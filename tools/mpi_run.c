/* mpi_run.c - see mpi_run.h. */
#define _POSIX_C_SOURCE 200809L
#include "mpi_run.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

enum { TAG_PROGRESS = 7001 };

void satf_mpi_wait(MPI_Request *req, MPI_Status *status) {
  struct timespec nap = {0, 1000000}; /* 1 ms */
  int done = 0;
  for (;;) {
    MPI_Test(req, &done, status);
    if (done)
      return;
    nanosleep(&nap, NULL);
  }
}

/* The variables Open MPI's mpirun, PMIx launchers (srun --mpi=pmix) and
 * PMI-1/2 launchers set in every rank's environment. */
static int launched_by_mpi(void) {
  return getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMIX_RANK") ||
         getenv("PMI_RANK");
}

int satf_mpi_start(const char *prog, int *argc, char ***argv, satf_mpi *m) {
  m->rank = 0;
  m->size = 1;
  m->active = 0;
  if (!launched_by_mpi())
    return 0;
  int provided = 0;
  /* Only the main thread calls MPI (worker threads never do). */
  if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) !=
      MPI_SUCCESS) {
    fprintf(stderr, "%s: cannot start MPI\n", prog);
    return -1;
  }
  m->active = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &m->rank);
  MPI_Comm_size(MPI_COMM_WORLD, &m->size);
  return 0;
}

void satf_mpi_stop(satf_mpi *m) {
  if (m->active)
    MPI_Finalize();
  m->active = 0;
}

_Noreturn void satf_mpi_fail(const satf_mpi *m, const char *prog,
                             const char *message) {
  if (m->size > 1)
    fprintf(stderr, "%s: rank %d of %d: %s (aborting every rank)\n", prog,
            m->rank, m->size, message);
  else
    fprintf(stderr, "%s: %s\n", prog, message);
  fflush(stderr);
  if (m->active)
    MPI_Abort(MPI_COMM_WORLD, 1);
  exit(1);
}

void satf_mpi_mute(const satf_mpi *m, int saved[2]) {
  saved[0] = saved[1] = -1;
  if (m->rank == 0)
    return;
  fflush(stdout);
  fflush(stderr);
  int null = open("/dev/null", O_WRONLY);
  if (null < 0)
    return;
  saved[0] = dup(1);
  saved[1] = dup(2);
  dup2(null, 1);
  dup2(null, 2);
  close(null);
}

void satf_mpi_unmute(int saved[2]) {
  fflush(stdout);
  fflush(stderr);
  for (int i = 0; i < 2; i++)
    if (saved[i] >= 0) {
      dup2(saved[i], i + 1);
      close(saved[i]);
      saved[i] = -1;
    }
}

int satf_mpi_share_status(const satf_mpi *m, int status) {
  if (m->active && m->size > 1) {
    MPI_Request req;
    MPI_Ibcast(&status, 1, MPI_INT, 0, MPI_COMM_WORLD, &req);
    satf_mpi_wait(&req, MPI_STATUS_IGNORE);
  }
  return status;
}

int satf_mpi_progress_begin(satf_mpi_progress *p, const satf_mpi *m,
                            satf_progress *bar, size_t mine) {
  p->m = m;
  p->bar = bar;
  p->mine = mine;
  p->total = mine;
  p->done = p->count = NULL;
  p->final = NULL;
  p->sending = 0;
  p->shown = (size_t)-1;
  p->req = MPI_REQUEST_NULL;
  if (m->size == 1)
    return 0;
  long long own = (long long)mine;
  if (m->rank == 0) {
    p->done = calloc((size_t)m->size, sizeof *p->done);
    p->count = calloc((size_t)m->size, sizeof *p->count);
    p->final = calloc((size_t)m->size, sizeof *p->final);
  }
  long long dummy = 0;
  MPI_Gather(&own, 1, MPI_LONG_LONG,
             m->rank == 0 && p->count ? p->count : &dummy, 1, MPI_LONG_LONG, 0,
             MPI_COMM_WORLD);
  if (m->rank == 0) {
    if (!p->done || !p->count || !p->final)
      return -1;
    p->total = 0;
    for (int r = 0; r < m->size; r++)
      p->total += (size_t)p->count[r];
  }
  return 0;
}

/* Rank 0 redraws when the job's count changed. */
static void draw(satf_mpi_progress *p) {
  size_t sum = 0;
  for (int r = 0; r < p->m->size; r++)
    sum += (size_t)p->done[r];
  if (sum != p->shown)
    satf_progress_update(p->bar, sum, p->total);
  p->shown = sum;
}

/* A rank's last message says -1 - count: the others say counts done. */
static void take(satf_mpi_progress *p, int from, long long v) {
  if (v < 0) {
    p->done[from] = -1 - v;
    p->final[from] = 1;
  } else {
    p->done[from] = v;
  }
}

/* Rank 0: takes every progress message that has arrived. */
static void poll(satf_mpi_progress *p) {
  for (;;) {
    int flag = 0;
    MPI_Status s;
    MPI_Iprobe(MPI_ANY_SOURCE, TAG_PROGRESS, MPI_COMM_WORLD, &flag, &s);
    if (!flag)
      return;
    long long v = 0;
    MPI_Recv(&v, 1, MPI_LONG_LONG, s.MPI_SOURCE, TAG_PROGRESS, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    take(p, s.MPI_SOURCE, v);
  }
}

void satf_mpi_progress_update(satf_mpi_progress *p, size_t done) {
  if (p->m->size == 1) {
    satf_progress_update(p->bar, done, p->total);
    return;
  }
  if (p->m->rank == 0) {
    p->done[0] = (long long)done;
    poll(p);
    draw(p);
    return;
  }
  int idle = 1;
  if (p->req != MPI_REQUEST_NULL)
    MPI_Test(&p->req, &idle, MPI_STATUS_IGNORE);
  if (idle && (long long)done != p->sending) {
    p->sending = (long long)done;
    MPI_Isend(&p->sending, 1, MPI_LONG_LONG, 0, TAG_PROGRESS, MPI_COMM_WORLD,
              &p->req);
  }
}

void satf_mpi_progress_finish(satf_mpi_progress *p) {
  if (p->m->size == 1)
    return;
  if (p->m->rank != 0) {
    /* one rank's messages arrive in order: this one is its last */
    if (p->req != MPI_REQUEST_NULL)
      satf_mpi_wait(&p->req, MPI_STATUS_IGNORE);
    p->sending = -1 - (long long)p->mine;
    MPI_Send(&p->sending, 1, MPI_LONG_LONG, 0, TAG_PROGRESS, MPI_COMM_WORLD);
    return;
  }
  p->done[0] = (long long)p->mine;
  p->final[0] = 1;
  draw(p);
  for (;;) {
    int r = 0;
    while (r < p->m->size && p->final[r])
      r++;
    if (r == p->m->size)
      break;
    long long v = 0;
    MPI_Status s;
    MPI_Request req;
    MPI_Irecv(&v, 1, MPI_LONG_LONG, MPI_ANY_SOURCE, TAG_PROGRESS,
              MPI_COMM_WORLD, &req);
    satf_mpi_wait(&req, &s);
    take(p, s.MPI_SOURCE, v);
    draw(p);
  }
}

void satf_mpi_progress_free(satf_mpi_progress *p) {
  free(p->done);
  free(p->count);
  free(p->final);
  p->done = p->count = NULL;
  p->final = NULL;
}
