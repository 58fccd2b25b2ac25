/* strands_ply_header.c - the PLY header ("ply", "format", "element",
 * "property" lines up to "end_header") and the cursor that reads one
 * property value at a time from an ascii, little- or big-endian body,
 * never past the end of the data. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "strands_ply.h"

enum { K_INT, K_UINT, K_FLOAT };
static const struct {
  const char *name, *alias;
  int size, kind;
} TYPES[] = {
    {"char", "int8", 1, K_INT},       {"uchar", "uint8", 1, K_UINT},
    {"short", "int16", 2, K_INT},     {"ushort", "uint16", 2, K_UINT},
    {"int", "int32", 4, K_INT},       {"uint", "uint32", 4, K_UINT},
    {"float", "float32", 4, K_FLOAT}, {"double", "float64", 8, K_FLOAT}};
enum { N_TYPES = sizeof TYPES / sizeof TYPES[0] };
#define PLY_MAX_HEADER 65536
#define PLY_MAX_LIST 1000000 /* values in one list */

static int type_find(const char *s) {
  for (int t = 0; t < N_TYPES; t++)
    if (strcmp(s, TYPES[t].name) == 0 || strcmp(s, TYPES[t].alias) == 0)
      return t;
  return -1;
}

/* One header line's words (at most 5 kept) into w; returns their count. */
static int split_words(char *line, char *w[5]) {
  int n = 0;
  for (char *t = strtok(line, " \t\r"); t && n < 5; t = strtok(NULL, " \t\r"))
    w[n++] = t;
  return n;
}

static satf_status header_line(const char *name, char *line, int lineno,
                               ply_header *h, satf_error *err) {
  char copy[256];
  snprintf(copy, sizeof copy, "%s", line);
  char *w[5];
  int n = split_words(line, w);
  if (n == 0 || strcmp(w[0], "comment") == 0 || strcmp(w[0], "obj_info") == 0)
    return SATF_OK;
  if (strcmp(w[0], "format") == 0 && n >= 2) {
    h->format = strcmp(w[1], "ascii") == 0                  ? PLY_ASCII
                : strcmp(w[1], "binary_little_endian") == 0 ? PLY_LE
                : strcmp(w[1], "binary_big_endian") == 0    ? PLY_BE
                                                            : -1;
    if (h->format < 0)
      return satf_error_set(err, SATF_ERR_FORMAT,
                            "%s: header line %d: unknown format \"%s\"", name,
                            lineno, w[1]);
    return SATF_OK;
  }
  if (strcmp(w[0], "element") == 0 && n == 3) {
    if (h->n_elements == PLY_MAX_ELEMENTS)
      return satf_error_set(err, SATF_ERR_FORMAT, "%s: more than %d elements",
                            name, PLY_MAX_ELEMENTS);
    char *end;
    unsigned long long count = strtoull(w[2], &end, 10);
    if (*end || w[2][0] == '-' || count > 0xFFFFFFFFull ||
        strlen(w[1]) >= PLY_MAX_NAME)
      return satf_error_set(err, SATF_ERR_FORMAT,
                            "%s: header line %d: bad element \"%s\"", name,
                            lineno, copy);
    ply_element *e = &h->elements[h->n_elements++];
    memset(e, 0, sizeof *e);
    snprintf(e->name, sizeof e->name, "%s", w[1]);
    e->count = count;
    return SATF_OK;
  }
  if (strcmp(w[0], "property") == 0 && h->n_elements > 0) {
    ply_element *e = &h->elements[h->n_elements - 1];
    ply_property p = {{0}, -1, 0, -1};
    const char *pname = NULL;
    if (n == 3) {
      p.type = type_find(w[1]);
      pname = w[2];
    } else if (n == 5 && strcmp(w[1], "list") == 0) {
      p.is_list = 1;
      p.count_type = type_find(w[2]);
      p.type = type_find(w[3]);
      pname = w[4];
    }
    if (!pname || p.type < 0 ||
        (p.is_list &&
         (p.count_type < 0 || TYPES[p.count_type].kind == K_FLOAT)) ||
        strlen(pname) >= PLY_MAX_NAME || e->n_props == PLY_MAX_PROPS)
      return satf_error_set(err, SATF_ERR_FORMAT,
                            "%s: header line %d: bad property \"%s\"", name,
                            lineno, copy);
    snprintf(p.name, sizeof p.name, "%s", pname);
    e->props[e->n_props++] = p;
    return SATF_OK;
  }
  return satf_error_set(err, SATF_ERR_FORMAT,
                        "%s: header line %d: cannot read \"%s\"", name, lineno,
                        copy);
}

/* The fewest bytes a record of e can take. */
static uint64_t min_record(const ply_element *e, int format) {
  uint64_t bytes = 0;
  for (int p = 0; p < e->n_props; p++)
    bytes += format == PLY_ASCII ? 2
             : e->props[p].is_list
                 ? (uint64_t)TYPES[e->props[p].count_type].size
                 : (uint64_t)TYPES[e->props[p].type].size;
  return bytes;
}

static satf_status check_counts(const char *name, const ply_header *h,
                                size_t left, satf_error *err) {
  uint64_t need = 0;
  for (int i = 0; i < h->n_elements; i++)
    need += h->elements[i].count * min_record(&h->elements[i], h->format);
  /* an ascii file's last value needs no separator after it */
  if (need > (uint64_t)left + (h->format == PLY_ASCII))
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: truncated: the header's element counts need "
                          "at least %llu bytes, the file has %zu after it",
                          name, (unsigned long long)need, left);
  return SATF_OK;
}

satf_status ply_parse_header(const void *data, size_t size, const char *name,
                             ply_header *h, ply_cursor *c, satf_error *err) {
  const char *b = data;
  memset(h, 0, sizeof *h);
  h->format = -1;
  if (size < 4 || (memcmp(b, "ply\n", 4) != 0 &&
                   (size < 5 || memcmp(b, "ply\r\n", 5) != 0)))
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: not a PLY file (no \"ply\" line first)", name);
  size_t at = b[3] == '\n' ? 4 : 5,
         limit = size < PLY_MAX_HEADER ? size : PLY_MAX_HEADER;
  char line[256];
  for (int lineno = 2;; lineno++) {
    const char *nl = memchr(b + at, '\n', limit - at);
    if (!nl)
      return satf_error_set(err, SATF_ERR_FORMAT,
                            "%s: the header has no \"end_header\" line", name);
    size_t len = (size_t)(nl - (b + at));
    if (len >= sizeof line)
      return satf_error_set(err, SATF_ERR_FORMAT,
                            "%s: header line %d is too long", name, lineno);
    memcpy(line, b + at, len);
    line[len] = '\0';
    at += len + 1;
    if (len && line[len - 1] == '\r')
      line[--len] = '\0';
    if (strcmp(line, "end_header") == 0)
      break;
    satf_status st = header_line(name, line, lineno, h, err);
    if (st != SATF_OK)
      return st;
  }
  if (h->format < 0)
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: the header has no \"format\" line", name);
  c->p = (const unsigned char *)b + at;
  c->end = (const unsigned char *)b + size;
  c->format = h->format;
  c->name = name;
  c->why[0] = '\0';
  return check_counts(name, h, size - at, err);
}

static int read_ascii(ply_cursor *c, double *out) {
  while (c->p < c->end &&
         (*c->p == ' ' || *c->p == '\t' || *c->p == '\n' || *c->p == '\r'))
    c->p++;
  char tok[64];
  size_t n = 0;
  while (c->p<c->end && * c->p> ' ' && n < sizeof tok - 1)
    tok[n++] = (char)*c->p++;
  tok[n] = '\0';
  char *end;
  *out = n ? strtod(tok, &end) : 0.0;
  if (n == 0 || *end || (c->p<c->end && * c->p> ' ')) {
    if (n)
      snprintf(c->why, sizeof c->why, "\"%.20s\" is not a number", tok);
    else
      snprintf(c->why, sizeof c->why, "the data ends early");
    return -1;
  }
  return 0;
}

static int read_binary(ply_cursor *c, int type, double *out) {
  int size = TYPES[type].size;
  if (c->end - c->p < size) {
    snprintf(c->why, sizeof c->why, "the data ends early");
    return -1;
  }
  uint64_t u = 0;
  for (int k = 0; k < size; k++) {
    int i = c->format == PLY_LE ? size - 1 - k : k;
    u = u << 8 | c->p[i];
  }
  c->p += size;
  if (TYPES[type].kind == K_UINT) {
    *out = (double)u;
  } else if (TYPES[type].kind == K_INT) {
    int shift = 64 - 8 * size;
    *out = (double)((int64_t)(u << shift) >> shift);
  } else if (size == 4) {
    uint32_t u32 = (uint32_t)u;
    float f;
    memcpy(&f, &u32, 4);
    *out = f;
  } else {
    memcpy(out, &u, 8);
  }
  return 0;
}

static int read_value(ply_cursor *c, int type, double *out) {
  return c->format == PLY_ASCII ? read_ascii(c, out)
                                : read_binary(c, type, out);
}

int ply_read_prop(ply_cursor *c, const ply_property *p, double *out) {
  if (!p->is_list)
    return read_value(c, p->type, out);
  double len, v;
  if (read_value(c, p->count_type, &len) != 0)
    return -1;
  if (!(len >= 0 && len <= PLY_MAX_LIST) || len != floor(len)) {
    snprintf(c->why, sizeof c->why, "list `%s` has an absurd length %g",
             p->name, len);
    return -1;
  }
  if (c->format != PLY_ASCII &&
      (double)(c->end - c->p) < len * TYPES[p->type].size) {
    snprintf(c->why, sizeof c->why, "the data ends early");
    return -1;
  }
  for (long k = 0; k < (long)len; k++)
    if (read_value(c, p->type, &v) != 0)
      return -1;
  *out = len;
  return 0;
}

int ply_skip_element(ply_cursor *c, const ply_element *e) {
  double v;
  if (e->n_props == 0)
    return 0; /* records of nothing: no need to count up to 2^32 */
  for (uint64_t r = 0; r < e->count; r++)
    for (int p = 0; p < e->n_props; p++)
      if (ply_read_prop(c, &e->props[p], &v) != 0)
        return -1;
  return 0;
}
