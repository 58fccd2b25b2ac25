/* maps_gpu_bytes.h - what the GPU's maps (maps_gpu.h, maps_gpu_fiber.h)
 * keep on the GPU, from the sizes alone: the uploads are sized by these,
 * and the memory estimate (budget.c) counts the same before anything is
 * built (on llvmpipe the driver's copies are the process's memory). */
#ifndef SATF_ONLINE_MAPS_GPU_BYTES_H
#define SATF_ONLINE_MAPS_GPU_BYTES_H

#include <stddef.h>

#include "maps.h"
#include "maps_fiber.h"

/* floats of a sector in the sectors' buffer: frame (9), features (3),
 * fibre direction (3: satf_shell_geom.hair, zero where it has none) */
#define MAPS_GPU_SECTOR_FLOATS 15

/* Neighbours per entry the GPU's maps read: opt's k_nearest in 1 to
 * SATF_DB_KMAX. */
int maps_gpu_k(const satf_map_options *opt);

/* Halfs of the kk pass's records: each record's reflectance, then its
 * alpha (maps_kk_cs.glsl). */
size_t maps_gpu_kk_halfs(const satf_build_params *p);
/* Halfs of the physical pass's records: every channel of the database
 * re-levelled to `channels` (maps_fiber_cs.glsl). */
size_t maps_gpu_fiber_halfs(const satf_build_params *p, int channels);
/* Bytes of a buffer of n halfs, two a word. */
size_t maps_gpu_half_bytes(size_t n);
/* Floats of the resampling table (maps_column_table: an index and a
 * fraction per column) for records `width` samples wide. */
size_t maps_gpu_column_floats(int width);
/* Floats of the physical mode's M_p table and orientation-free levels
 * (maps_fiber_tables). */
size_t maps_gpu_mp_floats(const maps_fiber_shape *s);
size_t maps_gpu_rel_floats(const satf_build_params *p,
                           const maps_fiber_shape *s);

/* What maps_gpu_create uploads once for database db: its records as halfs
 * and the tables beside them. fiber: the shape of what
 * satf_maps_fiber_create makes of db (the physical mode); NULL: the kk
 * mode. */
typedef struct maps_gpu_table_bytes {
  size_t records;
  size_t tables; /* resampling table, sample levels; M_p's, rel levels */
} maps_gpu_table_bytes;
void maps_gpu_tables_bytes(const satf_db *db, const maps_fiber_shape *fiber,
                           maps_gpu_table_bytes *out);

/* What one geometry of `sectors` sectors and `hsvs` HSVs takes: the
 * sectors' frames and features, then a neighbour entry (k pairs of index
 * and weight) per sector and per HSV. */
size_t maps_gpu_sector_bytes(size_t sectors);
size_t maps_gpu_neighbor_bytes(size_t sectors, size_t hsvs, int k);

#endif
