/* mpi_build.c - see mpi_build.h. Rank r builds part r of N
 * (satf_db_part_range): sample i depends only on (seed, i), so the database
 * rank 0 assembles is the one-process build's, byte for byte. */
#include "mpi_build.h"

#include <stdlib.h>

enum { TAG_DATA = 7101, TAG_GO = 7102 };

/* Large parts travel in chunks: MPI counts are ints, and a chunk at a time
 * is what the network and rank 0 hold in flight, not the whole part. */
#define CHUNK_FLOATS ((size_t)1 << 24) /* 64 MB */

/* A rank waits, napping (satf_mpi_wait), for rank 0 to ask for its part,
 * then sends at full speed: a transfer without single-copy support moves
 * fragment by fragment as both sides progress, which a napping sender
 * would slow down. */
static void send_floats(const float *data, size_t n) {
  for (size_t at = 0; at < n; at += CHUNK_FLOATS) {
    size_t k = n - at < CHUNK_FLOATS ? n - at : CHUNK_FLOATS;
    MPI_Send(data + at, (int)k, MPI_FLOAT, 0, TAG_DATA, MPI_COMM_WORLD);
  }
}

static void send_part(const float *features, const float *rec, int count,
                      size_t per) {
  int go = 0;
  MPI_Request req;
  MPI_Irecv(&go, 1, MPI_INT, 0, TAG_GO, MPI_COMM_WORLD, &req);
  satf_mpi_wait(&req, MPI_STATUS_IGNORE);
  send_floats(features, (size_t)count * SATF_FEATURES);
  send_floats(rec, (size_t)count * per);
}

/* Receives straight into place: rank 0 holds no copy of a part. */
static void recv_floats(float *data, size_t n, int from) {
  for (size_t at = 0; at < n; at += CHUNK_FLOATS) {
    size_t k = n - at < CHUNK_FLOATS ? n - at : CHUNK_FLOATS;
    MPI_Recv(data + at, (int)k, MPI_FLOAT, from, TAG_DATA, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
  }
}

static void on_progress(void *ctx, size_t done, size_t total) {
  (void)total;
  satf_mpi_progress_update(ctx, done);
}

/* Rank 0: the other ranks' parts, into the database. */
static void gather(const satf_mpi *m, const satf_build_params *p, satf_db *db) {
  size_t per = satf_db_sample_floats(p);
  for (int r = 1; r < m->size; r++) {
    int first, count;
    satf_db_part_range(p->samples, r, m->size, &first, &count);
    if (count == 0)
      continue;
    int go = 1;
    MPI_Send(&go, 1, MPI_INT, r, TAG_GO, MPI_COMM_WORLD);
    recv_floats(satf_db_sample_features(db, first),
                (size_t)count * SATF_FEATURES, r);
    recv_floats(satf_db_samples_mut(db, first), (size_t)count * per, r);
  }
}

satf_status satf_mpi_build(const satf_mpi *m, const satf_build_params *p,
                           int threads, satf_progress *bar, satf_db **out,
                           satf_mpi_build_times *times, satf_error *err) {
  *out = NULL;
  double t0 = satf_now_seconds();
  int first, count;
  satf_db_part_range(p->samples, m->rank, m->size, &first, &count);
  size_t per = satf_db_sample_floats(p);
  satf_db *db = NULL;
  float *rec = NULL, *features = NULL;
  satf_status st = SATF_OK;
  if (m->rank == 0) {
    st = satf_db_create(p, &db, err);
    if (st == SATF_OK) {
      rec = satf_db_samples_mut(db, first);
      features = satf_db_sample_features(db, first);
    }
  } else if (count > 0) {
    rec = malloc((size_t)count * per * sizeof(float));
    features = malloc((size_t)count * SATF_FEATURES * sizeof(float));
    if (!rec || !features)
      st = satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot allocate its part of %d samples", count);
  }
  satf_mpi_progress prog;
  if (st == SATF_OK &&
      satf_mpi_progress_begin(&prog, m, bar, (size_t)count) != 0)
    st = satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  if (st == SATF_OK)
    st = satf_build_range(p, first, count, threads, on_progress, &prog, rec,
                          features, err);
  if (st == SATF_OK) {
    satf_mpi_progress_finish(&prog);
    satf_mpi_progress_free(&prog);
    times->trace = satf_now_seconds() - t0;
    double t1 = satf_now_seconds();
    if (m->rank == 0) {
      gather(m, p, db);
    } else if (count > 0) {
      send_part(features, rec, count, per);
    }
    times->gather = satf_now_seconds() - t1;
  }
  if (m->rank != 0) {
    free(rec);
    free(features);
  }
  if (st == SATF_OK && db)
    st = satf_db_finalize(db, err);
  if (st != SATF_OK) {
    satf_db_destroy(db);
    return st;
  }
  *out = db;
  return SATF_OK;
}
