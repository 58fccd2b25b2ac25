/* mpi_frames.h - satf-render --frames across the ranks of an MPI job: each
 * rank renders its frames with its own headless context (frame f on rank
 * (f - first) mod N), through the sequence renderer, so --resume and the
 * atomic frame files work as in one process; rank 0 draws one progress
 * line, makes the contact sheet and reports the totals. */
#ifndef SATF_TOOLS_MPI_FRAMES_H
#define SATF_TOOLS_MPI_FRAMES_H

#include "mpi_run.h"
#include "satf/render.h"

/* Collective. On rank 0, *stats holds every rank's frames (means over all
 * rendered frames). A failing frame aborts the job (satf_mpi_fail): frames
 * already written stay, complete, for --resume. */
satf_status satf_mpi_frames(const satf_mpi *m, const char *prog,
                            satf_renderer *r, const satf_scene *scene,
                            const satf_sequence_opts *o,
                            satf_sequence_stats *stats, satf_error *err);

#endif
