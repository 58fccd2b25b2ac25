/* mpi_build.h - satf-build across the ranks of an MPI job: each rank builds
 * its part of the samples (satf_build_range on its threads), rank 0 receives
 * the other parts straight into its database and finalizes it. */
#ifndef SATF_TOOLS_MPI_BUILD_H
#define SATF_TOOLS_MPI_BUILD_H

#include "mpi_run.h"
#include "satf/offline.h"

typedef struct satf_mpi_build_times {
  double trace;  /* until every rank's part was traced */
  double gather; /* receiving the parts on rank 0 */
} satf_mpi_build_times;

/* Builds p across the ranks of m (each on `threads` threads); rank 0 draws
 * the progress of all of them on bar. Returns SATF_OK with the finalized
 * database in *out on rank 0 (NULL elsewhere); an error is this rank's own
 * (the caller aborts the job with satf_mpi_fail). */
satf_status satf_mpi_build(const satf_mpi *m, const satf_build_params *p,
                           int threads, satf_progress *bar, satf_db **out,
                           satf_mpi_build_times *times, satf_error *err);

#endif
