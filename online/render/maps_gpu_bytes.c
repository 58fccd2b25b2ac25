/* maps_gpu_bytes.c - see maps_gpu_bytes.h. */
#include "maps_gpu_bytes.h"

#include <stdint.h>

int maps_gpu_k(const satf_map_options *opt) {
  return opt->k_nearest < 1              ? 1
         : opt->k_nearest > SATF_DB_KMAX ? SATF_DB_KMAX
                                         : opt->k_nearest;
}

/* records of the database: a sample's every view and light azimuth */
static size_t records(const satf_build_params *p) {
  return (size_t)p->samples * (size_t)p->n_view * (size_t)p->n_light;
}

size_t maps_gpu_kk_halfs(const satf_build_params *p) {
  return records(p) * 2 * (size_t)p->trace.width;
}

size_t maps_gpu_fiber_halfs(const satf_build_params *p, int channels) {
  return records(p) * (size_t)channels * (size_t)p->trace.width;
}

size_t maps_gpu_half_bytes(size_t n) { return (n + 1) / 2 * sizeof(uint32_t); }

size_t maps_gpu_column_floats(int width) {
  return (size_t)MAPS_AZIMUTH_BINS * (size_t)width * 2;
}

size_t maps_gpu_mp_floats(const maps_fiber_shape *s) {
  return (size_t)s->mp_size * (size_t)s->mp_size * 4; /* four lobes */
}

size_t maps_gpu_rel_floats(const satf_build_params *p,
                           const maps_fiber_shape *s) {
  return (size_t)p->samples * (size_t)s->rel_bins * (size_t)s->rel_stride;
}

void maps_gpu_tables_bytes(const satf_db *db, const maps_fiber_shape *fiber,
                           maps_gpu_table_bytes *out) {
  const satf_build_params *p = satf_db_params(db);
  out->records = maps_gpu_half_bytes(
      fiber ? maps_gpu_fiber_halfs(p, fiber->channels) : maps_gpu_kk_halfs(p));
  size_t floats = maps_gpu_column_floats(p->trace.width) + (size_t)p->samples;
  if (fiber)
    floats += maps_gpu_mp_floats(fiber) + maps_gpu_rel_floats(p, fiber);
  out->tables = floats * sizeof(float);
}

size_t maps_gpu_sector_bytes(size_t sectors) {
  return sectors * MAPS_GPU_SECTOR_FLOATS * sizeof(float);
}

size_t maps_gpu_neighbor_bytes(size_t sectors, size_t hsvs, int k) {
  return (sectors + hsvs) * 2 * (size_t)k * sizeof(uint32_t);
}
