/* strands_detect.c - which strand format a file's bytes are, so a file is
 * read by what it is and one with a misleading name is called by its
 * format. Each test is cheap and the formats' signatures exclude each
 * other: "HAIR", "ply\n", a TressFX version float (a .data strand count
 * read as a float is a denormal), .data counts that fill the file, and OBJ
 * text (its first statement one of OBJ's keywords). */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "le_bytes.h"
#include "satf/import.h"
#include "strands_formats.h"

/* The .data records walked by their counts end exactly at the end. */
static int usc_plausible(const unsigned char *b, size_t size) {
  if (size < 4)
    return 0;
  int32_t n = (int32_t)le32(b);
  if (n <= 0 || (uint64_t)n * 4 > size - 4)
    return 0;
  size_t at = 4;
  for (int32_t i = 0; i < n; i++) {
    if (size - at < 4)
      return 0;
    int32_t m = (int32_t)le32(b + at);
    at += 4;
    if (m < 0 || (size - at) / 12 < (size_t)m)
      return 0;
    at += 12 * (size_t)m;
  }
  return at == size;
}

/* Text whose first line that is neither blank nor a comment starts with an
 * OBJ statement; the bytes up to there must be printable. */
static int obj_plausible(const unsigned char *b, size_t size) {
  static const char *const kw[] = {"v ",      "vn ",     "vt ", "l ",
                                   "f ",      "o ",      "g ",  "s ",
                                   "mtllib ", "usemtl ", NULL};
  size_t at = 0, scan = size < 65536 ? size : 65536;
  while (at < scan) {
    while (at < scan &&
           (b[at] == ' ' || b[at] == '\t' || b[at] == '\r' || b[at] == '\n'))
      at++;
    if (at < scan && b[at] == '#') { /* a comment: to its end of line */
      for (; at < scan && b[at] != '\n'; at++)
        if (b[at] < 0x09 || b[at] == 0x7f)
          return 0;
      continue;
    }
    for (int k = 0; kw[k]; k++) {
      size_t n = strlen(kw[k]);
      if (size - at >= n && memcmp(b + at, kw[k], n) == 0)
        return 1;
    }
    return 0;
  }
  return 0;
}

satf_strands_format satf_strands_detect(const void *data, size_t size) {
  const unsigned char *b = data;
  if (size >= 4 && memcmp(b, "HAIR", 4) == 0)
    return SATF_STRANDS_HAIR;
  if ((size >= 4 && memcmp(b, "ply\n", 4) == 0) ||
      (size >= 5 && memcmp(b, "ply\r\n", 5) == 0))
    return SATF_STRANDS_PLY;
  /* TressFX 3.x and 4.x headers are 296 and 160 bytes */
  if (size >= 160) {
    if (strands_tfx_version_plausible(lef32(b)))
      return SATF_STRANDS_TFX;
  }
  if (usc_plausible(b, size))
    return SATF_STRANDS_USC;
  if (obj_plausible(b, size))
    return SATF_STRANDS_OBJ;
  return SATF_STRANDS_UNKNOWN;
}

static int has_suffix(const char *s, const char *suffix) {
  size_t n = strlen(s), k = strlen(suffix);
  return n >= k && strcmp(s + n - k, suffix) == 0;
}

satf_strands_format satf_strands_format_of_name(const char *path) {
  return has_suffix(path, ".hair")   ? SATF_STRANDS_HAIR
         : has_suffix(path, ".tfx")  ? SATF_STRANDS_TFX
         : has_suffix(path, ".ply")  ? SATF_STRANDS_PLY
         : has_suffix(path, ".data") ? SATF_STRANDS_USC
         : has_suffix(path, ".obj")  ? SATF_STRANDS_OBJ
                                     : SATF_STRANDS_UNKNOWN;
}

const char *satf_strands_format_name(satf_strands_format f) {
  switch (f) {
  case SATF_STRANDS_HAIR: return "cyHair";
  case SATF_STRANDS_TFX: return "TressFX";
  case SATF_STRANDS_PLY: return "PLY";
  case SATF_STRANDS_USC: return "USC-HairSalon .data";
  case SATF_STRANDS_OBJ: return "OBJ";
  default: return "unknown";
  }
}
