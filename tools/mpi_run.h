/* mpi_run.h - the MPI glue shared by satf-build and satf-render (compiled
 * only when CMake finds MPI: SATF_MPI). The libraries stay MPI-free: they
 * build sample ranges and render frame ranges; this file starts MPI when
 * the process was launched by mpirun or srun, shows one progress line for
 * the work of every rank (rank 0 prints it), and aborts the whole job with
 * a message naming the rank when one fails. */
#ifndef SATF_TOOLS_MPI_RUN_H
#define SATF_TOOLS_MPI_RUN_H

#include <mpi.h>
#include <stddef.h>

#include "satf/common.h"

typedef struct satf_mpi {
  int rank, size;
  int active; /* MPI was started (launched by mpirun / srun) */
} satf_mpi;

/* Starts MPI when a launcher's environment says this process is one rank
 * of a job (OMPI_COMM_WORLD_SIZE, PMIX_RANK, PMI_RANK); otherwise leaves
 * MPI alone and makes this rank 0 of 1, so a plain run needs no MPI
 * runtime. Returns 0, or -1 after printing why MPI did not start. */
int satf_mpi_start(const char *prog, int *argc, char ***argv, satf_mpi *m);
/* Finalizes MPI when it was started. */
void satf_mpi_stop(satf_mpi *m);
/* Prints "PROG: rank R of N: MESSAGE" on stderr and aborts every rank of
 * the job with exit status 1 (MPI_Abort); without MPI, exits 1. */
_Noreturn void satf_mpi_fail(const satf_mpi *m, const char *prog,
                             const char *message);
/* On ranks other than 0, sends stdout and stderr to /dev/null until
 * satf_mpi_unmute, so --help and argument errors print once. */
void satf_mpi_mute(const satf_mpi *m, int saved[2]);
void satf_mpi_unmute(int saved[2]);
/* Waits for a request without spinning (a 1 ms nap between tests): Open
 * MPI's blocking calls poll a core at 100% while they wait, which on a
 * node running as many ranks as cores takes a core from the ranks still
 * working. */
void satf_mpi_wait(MPI_Request *req, MPI_Status *status);
/* Rank 0's exit status, given to every rank (a collective call). */
int satf_mpi_share_status(const satf_mpi *m, int status);

/* Progress of work split across the ranks: each rank counts its own items
 * done; rank 0 gathers the counts without blocking anyone (small messages
 * polled when it updates) and draws one progress line for the whole job.
 * The other ranks send at most one message per update in flight. */
typedef struct satf_mpi_progress {
  const satf_mpi *m;
  satf_progress *bar; /* rank 0's line (may be quiet) */
  size_t total;       /* items of every rank */
  size_t mine;        /* this rank's items */
  long long *done;    /* rank 0: items done per rank */
  long long *count;   /* rank 0: items per rank */
  int *final;         /* rank 0: the rank's last count has come */
  long long sending;  /* other ranks: the count in flight */
  size_t shown;       /* rank 0: the count last drawn */
  MPI_Request req;
} satf_mpi_progress;

/* Collective: every rank passes its own item count. */
int satf_mpi_progress_begin(satf_mpi_progress *p, const satf_mpi *m,
                            satf_progress *bar, size_t mine);
/* This rank has done `done` of its items; rank 0 also redraws. */
void satf_mpi_progress_update(satf_mpi_progress *p, size_t done);
/* This rank is done: the others report their last count, rank 0 waits for
 * every rank's last count (drawing as they come). */
void satf_mpi_progress_finish(satf_mpi_progress *p);
void satf_mpi_progress_free(satf_mpi_progress *p);

#endif
