/* le_bytes.h - little-endian 32-bit integers and floats in strand files
 * (cyHair and TressFX store both), read and written byte by byte so the
 * readers work on any host and any alignment. */
#ifndef SATF_IMPORT_LE_BYTES_H
#define SATF_IMPORT_LE_BYTES_H

#include <stdint.h>
#include <string.h>

static inline uint32_t le32(const unsigned char *p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
         (uint32_t)p[3] << 24;
}

static inline float lef32(const unsigned char *p) {
  uint32_t u = le32(p);
  float f;
  memcpy(&f, &u, sizeof f);
  return f;
}

static inline void put32(unsigned char *p, uint32_t v) {
  p[0] = (unsigned char)v;
  p[1] = (unsigned char)(v >> 8);
  p[2] = (unsigned char)(v >> 16);
  p[3] = (unsigned char)(v >> 24);
}

static inline void putf32(unsigned char *p, float f) {
  uint32_t u;
  memcpy(&u, &f, sizeof u);
  put32(p, u);
}

#endif
