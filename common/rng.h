/* rng.h - small deterministic random numbers (splitmix64 seeding, xoshiro128+
 * style generation is not needed: splitmix64 alone is fast and passes
 * BigCrush for our use). Stream i of seed s is independent of thread count,
 * which is what makes database builds bit-identical across --threads. */
#ifndef SATF_COMMON_RNG_H
#define SATF_COMMON_RNG_H

#include <stdint.h>

typedef struct satf_rng {
  uint64_t state;
} satf_rng;

/* Seeds stream `stream` of master seed `seed`. */
void satf_rng_seed(satf_rng *rng, uint64_t seed, uint64_t stream);
uint64_t satf_rng_u64(satf_rng *rng);
/* Uniform in [0, 1) with 53 random bits. */
double satf_rng_uniform(satf_rng *rng);
/* Uniform in [lo, hi). */
double satf_rng_range(satf_rng *rng, double lo, double hi);
/* Uniform integer in [0, n), n > 0. */
uint32_t satf_rng_below(satf_rng *rng, uint32_t n);
/* Standard normal (Box-Muller, one value per call). */
double satf_rng_normal(satf_rng *rng);

#endif
