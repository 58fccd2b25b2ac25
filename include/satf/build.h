/* build.h - building an HRIR database (SATF sec. 5): random generalized
 * sectors, planar ray traced under every view x light azimuth pair. */
#ifndef SATF_BUILD_H
#define SATF_BUILD_H

#include "satf/db.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Called on the calling thread about every 100 ms with samples done. */
typedef void (*satf_build_progress)(void *ctx, size_t done, size_t total);

/* Builds and finalizes a database on `threads` threads (0 = all cores).
 * Sample i depends only on (p->seed, i), so the result is bit-identical for
 * any thread count. */
satf_status satf_build(const satf_build_params *p, int threads,
                       satf_build_progress progress, void *progress_ctx,
                       satf_db **out, satf_error *err);

/* The sector of sample i of a build (for tests and held-out checks);
 * destroy with satf_sector_destroy. */
satf_status satf_build_sector(const satf_build_params *p, uint64_t seed,
                              uint64_t index, satf_sector **out,
                              satf_error *err);

#ifdef __cplusplus
}
#endif
#endif
