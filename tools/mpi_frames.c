/* mpi_frames.c - see mpi_frames.h. */
#include "mpi_frames.h"

#include <string.h>

/* This rank's frames, one sequence call each; the sums of their timings
 * (mean x rendered) in sum. */
static void render_mine(const satf_mpi *m, const char *prog, satf_renderer *r,
                        const satf_scene *scene, const satf_sequence_opts *o,
                        satf_mpi_progress *prog_all, satf_sequence_stats *sum) {
  size_t done = 0;
  satf_error err;
  satf_error_clear(&err);
  for (int f = o->first + m->rank; f <= o->last; f += m->size) {
    satf_sequence_opts one = *o;
    one.first = one.last = f;
    one.quiet = 1;
    one.contact_sheet = NULL; /* rank 0 makes it from the files */
    satf_sequence_stats s;
    if (satf_sequence_render(r, scene, &one, &s, &err) != SATF_OK)
      satf_mpi_fail(m, prog, err.message);
    sum->rendered += s.rendered;
    sum->skipped += s.skipped;
    sum->mean.index_ms += s.mean.index_ms * s.rendered;
    sum->mean.maps_ms += s.mean.maps_ms * s.rendered;
    sum->mean.upload_ms += s.mean.upload_ms * s.rendered;
    sum->mean.lighting_ms += s.mean.lighting_ms * s.rendered;
    sum->mean.shadow_ms += s.mean.shadow_ms * s.rendered;
    sum->mean.total_ms += s.mean.total_ms * s.rendered;
    satf_mpi_progress_update(prog_all, ++done);
  }
}

static size_t frames_of_rank(const satf_sequence_opts *o, int rank, int size) {
  int count = o->last - o->first + 1;
  return count > rank ? (size_t)((count - rank + size - 1) / size) : 0;
}

satf_status satf_mpi_frames(const satf_mpi *m, const char *prog,
                            satf_renderer *r, const satf_scene *scene,
                            const satf_sequence_opts *o,
                            satf_sequence_stats *stats, satf_error *err) {
  memset(stats, 0, sizeof *stats);
  satf_status st = SATF_OK;
  if (o->exr_pattern)
    st = satf_sequence_check_pattern(o->exr_pattern, err);
  if (st == SATF_OK && o->png_pattern)
    st = satf_sequence_check_pattern(o->png_pattern, err);
  if (st == SATF_OK && o->contact_sheet && !o->exr_pattern)
    st = satf_error_set(err, SATF_ERR_ARGUMENT,
                        "under MPI, --contact-sheet is made from the EXR "
                        "frames: give -o too");
  if (st != SATF_OK)
    satf_mpi_fail(m, prog, err->message);
  double t0 = satf_now_seconds();
  satf_progress bar;
  satf_progress_begin(&bar, stderr, "rendering", "frames", 1,
                      o->quiet || m->rank != 0);
  satf_mpi_progress all;
  if (satf_mpi_progress_begin(&all, m, &bar,
                              frames_of_rank(o, m->rank, m->size)) != 0)
    satf_mpi_fail(m, prog, "out of memory");
  satf_sequence_stats sum;
  memset(&sum, 0, sizeof sum);
  render_mine(m, prog, r, scene, o, &all, &sum);
  satf_mpi_progress_finish(&all);
  satf_mpi_progress_free(&all);
  satf_progress_end(&bar);
  int counts[2] = {sum.rendered, sum.skipped}, total_counts[2] = {0, 0};
  double ms[6] = {sum.mean.index_ms,    sum.mean.maps_ms,   sum.mean.upload_ms,
                  sum.mean.lighting_ms, sum.mean.shadow_ms, sum.mean.total_ms},
         total_ms[6] = {0};
  /* a rank done early waits here for the others without taking a core */
  MPI_Request req[2];
  MPI_Ireduce(counts, total_counts, 2, MPI_INT, MPI_SUM, 0, MPI_COMM_WORLD,
              &req[0]);
  MPI_Ireduce(ms, total_ms, 6, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD, &req[1]);
  satf_mpi_wait(&req[0], MPI_STATUS_IGNORE);
  satf_mpi_wait(&req[1], MPI_STATUS_IGNORE);
  if (m->rank != 0)
    return SATF_OK;
  stats->rendered = total_counts[0];
  stats->skipped = total_counts[1];
  double n = stats->rendered > 0 ? stats->rendered : 1;
  stats->mean.index_ms = total_ms[0] / n;
  stats->mean.maps_ms = total_ms[1] / n;
  stats->mean.upload_ms = total_ms[2] / n;
  stats->mean.lighting_ms = total_ms[3] / n;
  stats->mean.shadow_ms = total_ms[4] / n;
  stats->mean.total_ms = total_ms[5] / n;
  if (o->contact_sheet) {
    /* every frame is on disk now: a resumed pass over the range skips
     * them all and puts their thumbnails on the sheet */
    satf_sequence_opts sheet = *o;
    sheet.resume = 1;
    sheet.quiet = 1;
    satf_sequence_stats ignore;
    st = satf_sequence_render(r, scene, &sheet, &ignore, err);
  }
  stats->seconds = satf_now_seconds() - t0;
  return st;
}
