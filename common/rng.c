/* rng.c - splitmix64 (Steele, Lea, Flood 2014). */
#include "satf/common.h"

#include <math.h>

static uint64_t splitmix64_next(uint64_t *x) {
  uint64_t z = (*x += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

void satf_rng_seed(satf_rng *rng, uint64_t seed, uint64_t stream) {
  /* Mix seed and stream through the finaliser so neighbouring streams of
   * neighbouring seeds do not overlap. */
  uint64_t s = seed ^ (stream * 0xD1B54A32D192ED03ull);
  rng->state = splitmix64_next(&s);
}

uint64_t satf_rng_u64(satf_rng *rng) { return splitmix64_next(&rng->state); }

double satf_rng_uniform(satf_rng *rng) {
  return (double)(satf_rng_u64(rng) >> 11) * 0x1.0p-53;
}

double satf_rng_range(satf_rng *rng, double lo, double hi) {
  return lo + (hi - lo) * satf_rng_uniform(rng);
}

uint32_t satf_rng_below(satf_rng *rng, uint32_t n) {
  return (uint32_t)(((satf_rng_u64(rng) >> 32) * (uint64_t)n) >> 32);
}

double satf_rng_normal(satf_rng *rng) {
  double u1 = 1.0 - satf_rng_uniform(rng); /* (0, 1] so log is finite */
  double u2 = satf_rng_uniform(rng);
  return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}
