/* half.h - IEEE 754 binary16 ("half float") conversion for the map
 * textures: the renderer keeps every cluster's maps as GL_RGBA16F (half
 * the bytes of RGBA32F to write, keep and upload), built
 * in floats and packed here. Rounding is to nearest, ties to even, as
 * Imath's half and the F16C instructions do; values beyond the largest
 * half (65504) become infinity, NaN stays NaN. */
#ifndef SATF_ONLINE_HALF_H
#define SATF_ONLINE_HALF_H

#include <stddef.h>
#include <stdint.h>

/* dst[i] = half(src[i]) for i < n: F16C where the processor has it (x86-64,
 * chosen at run time), else half_pack_portable. */
void half_pack(const float *src, uint16_t *dst, size_t n);
/* A packer for output no one reads soon (maps far larger than the
 * cache), chosen once (the processor check is a CPUID, slow in a virtual
 * machine) for many short runs: with F16C, whole vectors to a 16-byte
 * aligned dst are stored past the cache (non-temporal), so a store does
 * not first read its line from memory; the same values as half_pack.
 * Call half_stream_end before another thread reads dst. */
typedef void (*half_pack_fn)(const float *src, uint16_t *dst, size_t n);
half_pack_fn half_stream_packer(void);
/* Orders the streamed stores before whatever follows (a fence). */
void half_stream_end(void);
/* dst[i] = float(src[i]) (exact: every half is a float). */
void half_unpack(const uint16_t *src, float *dst, size_t n);

/* The same without F16C (what other processors run; tests compare). */
void half_pack_portable(const float *src, uint16_t *dst, size_t n);
void half_unpack_portable(const uint16_t *src, float *dst, size_t n);

#endif
