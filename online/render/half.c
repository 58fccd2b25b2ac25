/* half.c - see half.h. */
#include "half.h"
#include "satf/common.h"

#include <Imath/half.h>

/* The F16C path: GCC or clang on x86-64, the instructions enabled for
 * these functions alone and chosen when the processor reports them. */
#if (defined(__GNUC__) || defined(__clang__)) && defined(__x86_64__)
#include <immintrin.h>
#define HALF_F16C 1

/* stream: the vectors stored past the cache (dst 16-byte aligned) */
__attribute__((target("avx,f16c"))) static void
pack_f16c_to(const float *src, uint16_t *dst, size_t n, int stream) {
  size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    __m128i h =
        _mm256_cvtps_ph(_mm256_loadu_ps(src + i), _MM_FROUND_TO_NEAREST_INT);
    if (stream)
      _mm_stream_si128((__m128i *)(dst + i), h);
    else
      _mm_storeu_si128((__m128i *)(dst + i), h);
  }
  half_pack_portable(src + i, dst + i, n - i);
}

static void pack_f16c(const float *src, uint16_t *dst, size_t n) {
  pack_f16c_to(src, dst, n, 0);
}

static void pack_stream_f16c(const float *src, uint16_t *dst, size_t n) {
  pack_f16c_to(src, dst, n, ((uintptr_t)dst & 15) == 0);
}

__attribute__((target("avx,f16c"))) static void
unpack_f16c(const uint16_t *src, float *dst, size_t n) {
  size_t i = 0;
  for (; i + 8 <= n; i += 8)
    _mm256_storeu_ps(
        dst + i, _mm256_cvtph_ps(_mm_loadu_si128((const __m128i *)(src + i))));
  half_unpack_portable(src + i, dst + i, n - i);
}

static int have_f16c(void) { return satf_cpu_has_f16c(0); }
#endif

void half_pack_portable(const float *src, uint16_t *dst, size_t n) {
  for (size_t i = 0; i < n; i++)
    dst[i] = imath_float_to_half(src[i]);
}

void half_unpack_portable(const uint16_t *src, float *dst, size_t n) {
  for (size_t i = 0; i < n; i++)
    dst[i] = imath_half_to_float(src[i]);
}

void half_pack(const float *src, uint16_t *dst, size_t n) {
#ifdef HALF_F16C
  if (have_f16c()) {
    pack_f16c(src, dst, n);
    return;
  }
#endif
  half_pack_portable(src, dst, n);
}

half_pack_fn half_stream_packer(void) {
#ifdef HALF_F16C
  if (have_f16c())
    return pack_stream_f16c;
#endif
  return half_pack_portable;
}

void half_stream_end(void) {
#ifdef HALF_F16C
  _mm_sfence();
#endif
}

void half_unpack(const uint16_t *src, float *dst, size_t n) {
#ifdef HALF_F16C
  if (have_f16c()) {
    unpack_f16c(src, dst, n);
    return;
  }
#endif
  half_unpack_portable(src, dst, n);
}
