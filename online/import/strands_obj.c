/* strands_obj.c - strand hair in Wavefront OBJ files, as Blender, Houdini
 * and Maya export curves: `v x y z` vertices, a fourth number (the
 * rational weight of the OBJ specification, 1 as exporters write it:
 * accepted and dropped, never a width) and the `v x y z r g b` vertex-colour
 * extension (MeshLab's, ZBrush's and most readers': kept as the points'
 * colours when every vertex has one). OBJ has no per-vertex width, and
 * none of those exporters writes one: the strands take the importer's
 * width (a fibre's, or --strand-width). `l` polylines of 1-based (or
 * negative, relative) vertex indices, `v/vt` pairs allowed. Every `l` line's
 * segments are chained into strands, so a file of two-vertex lines (Blender's
 * loose edges) reads like one of whole polylines; each chain runs from its
 * lower-numbered end (a strand's root is its first vertex as exporters write
 * them). Faces, normals, texture coordinates, groups and materials are skipped:
 * a groom exported with its head reads as its hair. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "satf/import.h"
#include "strands_ply.h"
#include "strands_read.h"

typedef struct obj_cursor {
  const char *at, *end;
  uint64_t line;
} obj_cursor;

/* The next line's bounds (without its end of line); 0 at the end. */
static int next_line(obj_cursor *c, const char **b, const char **e) {
  if (c->at >= c->end)
    return 0;
  *b = c->at;
  const char *nl = memchr(c->at, '\n', (size_t)(c->end - c->at));
  *e = nl ? nl : c->end;
  c->at = nl ? nl + 1 : c->end;
  c->line++;
  if (*e > *b && (*e)[-1] == '\r')
    (*e)--;
  return 1;
}

static const char *skip_space(const char *p, const char *e) {
  while (p < e && (*p == ' ' || *p == '\t'))
    p++;
  return p;
}

/* Whether the line's keyword is kw (followed by a blank or its end). */
static int keyword(const char *b, const char *e, const char *kw) {
  size_t n = strlen(kw);
  return (size_t)(e - b) >= n && memcmp(b, kw, n) == 0 &&
         (b + n == e || b[n] == ' ' || b[n] == '\t');
}

/* One number of a line, the text copied out so strtod cannot run past it. */
static int read_number(const char **p, const char *e, double *out) {
  const char *s = skip_space(*p, e);
  char buf[64];
  size_t n = 0;
  while (s + n < e && s[n] != ' ' && s[n] != '\t')
    n++;
  if (n == 0 || n >= sizeof buf)
    return -1;
  memcpy(buf, s, n);
  buf[n] = '\0';
  char *end;
  *out = strtod(buf, &end);
  if (end != buf + n)
    return -1;
  *p = s + n;
  return 0;
}

/* One vertex of an `l` line ("i", "i/t"), as a 0-based index into the nv
 * vertices read so far; -1 when absent or out of range. */
static int64_t read_index(const char **p, const char *e, uint64_t nv) {
  const char *s = skip_space(*p, e);
  char buf[32];
  size_t n = 0, k = 0;
  while (s + n < e && s[n] != ' ' && s[n] != '\t')
    n++;
  while (k < n && s[k] != '/')
    k++;
  if (k == 0 || k >= sizeof buf)
    return -1;
  memcpy(buf, s, k);
  buf[k] = '\0';
  char *end;
  long long i = strtoll(buf, &end, 10);
  *p = s + n;
  if (end != buf + k || i == 0)
    return -1;
  int64_t at = i > 0 ? (int64_t)i - 1 : (int64_t)nv + i;
  return at >= 0 && (uint64_t)at < nv ? at : -1;
}

/* Counts `v` lines and `l` segments (an upper bound: the blanks between
 * indices), so the arrays are sized before anything is read. */
static void count_statements(const void *data, size_t size, uint64_t *nv,
                             uint64_t *nseg, uint64_t *nfaces) {
  obj_cursor c = {data, (const char *)data + size, 0};
  const char *b, *e;
  *nv = *nseg = *nfaces = 0;
  while (next_line(&c, &b, &e)) {
    b = skip_space(b, e);
    if (keyword(b, e, "v"))
      (*nv)++;
    else if (keyword(b, e, "f"))
      (*nfaces)++;
    else if (keyword(b, e, "l"))
      for (const char *p = b + 1; p < e; p++)
        *nseg += (*p == ' ' || *p == '\t') && p + 1 < e && p[1] != ' ' &&
                 p[1] != '\t';
  }
}

/* One `v` line into xyz, and its colour, if it has one, into rgb (*coloured
 * counts the vertices that had). */
static satf_status parse_vertex(const obj_cursor *c, const char *name,
                                const char *p, const char *e, float *xyz,
                                float *rgb, uint64_t *coloured,
                                satf_error *err) {
  double v[7];
  int n = 0;
  while (n < 7 && skip_space(p, e) < e && read_number(&p, e, &v[n]) == 0)
    n++;
  if (skip_space(p, e) < e || (n != 3 && n != 4 && n != 6 && n != 7))
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: line %llu: a vertex is `v x y z` with an "
                          "optional weight or r g b colour",
                          name, (unsigned long long)c->line);
  for (int k = 0; k < n; k++)
    if (!isfinite(v[k]) || (k < 3 && fabs(v[k]) > 3.4e38))
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: line %llu: vertex value %g is not a finite "
                            "float",
                            name, (unsigned long long)c->line, v[k]);
  for (int k = 0; k < 3; k++)
    xyz[k] = (float)v[k];
  if (n >= 6) { /* x y z r g b, or x y z w r g b */
    for (int k = 0; k < 3; k++)
      rgb[k] = (float)v[n - 3 + k];
    (*coloured)++;
  }
  return SATF_OK;
}

/* An `l` line's segments appended to edges (pairs of 0-based indices). */
static satf_status parse_line(const obj_cursor *c, const char *name,
                              const char *p, const char *e, uint64_t nv,
                              int64_t *edges, uint64_t *n_edges,
                              satf_error *err) {
  int64_t prev = -1;
  int n = 0;
  while (skip_space(p, e) < e) {
    int64_t i = read_index(&p, e, nv);
    if (i < 0)
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: line %llu: a polyline vertex is not an "
                            "index of the %llu vertices above it",
                            name, (unsigned long long)c->line,
                            (unsigned long long)nv);
    if (n++ > 0 && i != prev) { /* a repeated index adds no segment */
      edges[2 * *n_edges] = prev;
      edges[2 * *n_edges + 1] = i;
      (*n_edges)++;
    }
    prev = i;
  }
  if (n < 2)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: line %llu: a polyline needs two vertices or "
                          "more",
                          name, (unsigned long long)c->line);
  return SATF_OK;
}

static satf_status parse_body(const void *data, size_t size, const char *name,
                              float *xyz, float *rgb, uint64_t *coloured,
                              int64_t *edges, uint64_t *n_edges,
                              satf_error *err) {
  obj_cursor c = {data, (const char *)data + size, 0};
  const char *b, *e;
  uint64_t nv = 0;
  *n_edges = 0;
  *coloured = 0;
  while (next_line(&c, &b, &e)) {
    b = skip_space(b, e);
    if (memchr(b, '\0', (size_t)(e - b)))
      return satf_error_set(err, SATF_ERR_FORMAT,
                            "%s: line %llu: a NUL byte: not an OBJ text file",
                            name, (unsigned long long)c.line);
    satf_status st = SATF_OK;
    if (keyword(b, e, "v"))
      st = parse_vertex(&c, name, b + 1, e, xyz + 3 * nv, rgb + 3 * nv,
                        coloured, err),
      nv++;
    else if (keyword(b, e, "l"))
      st = parse_line(&c, name, b + 1, e, nv, edges, n_edges, err);
    if (st != SATF_OK)
      return st;
  }
  return SATF_OK;
}

satf_status satf_obj_parse(const void *data, size_t size, const char *name,
                           satf_strand_set **out, satf_error *err) {
  *out = NULL;
  if (!name)
    name = "<obj>";
  uint64_t nv, nseg, nfaces;
  count_statements(data, size, &nv, &nseg, &nfaces);
  if (nseg == 0)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: no polylines (`l` lines)%s: nothing says "
                          "which vertices form a strand (export the hair as "
                          "curves or edges)",
                          name, nfaces ? ", only faces" : "");
  if (nv > SATF_STRANDS_MAX_POINTS)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: absurd vertex count %llu (at most %u)", name,
                          (unsigned long long)nv, SATF_STRANDS_MAX_POINTS);
  float *xyz = malloc((nv ? nv : 1) * 3 * sizeof(float));
  float *rgb = malloc((nv ? nv : 1) * 3 * sizeof(float));
  int64_t *edges = malloc(2 * nseg * sizeof(int64_t));
  satf_status st = SATF_OK;
  uint64_t n_edges = 0, coloured = 0;
  if (!xyz || !rgb || !edges)
    st = satf_error_set(err, SATF_ERR_NOMEM, "%s: cannot hold %llu vertices",
                        name, (unsigned long long)nv);
  if (st == SATF_OK)
    st =
        parse_body(data, size, name, xyz, rgb, &coloured, edges, &n_edges, err);
  /* colours only when every vertex has one: a strand half coloured has
   * no colour to give the rest */
  if (st == SATF_OK)
    st = ply_strands_from_edges(name, xyz, coloured == nv ? rgb : NULL, nv,
                                edges, n_edges, out, err);
  free(xyz);
  free(rgb);
  free(edges);
  return st;
}

satf_status satf_obj_read(const char *path, satf_strand_set **out,
                          satf_error *err) {
  return strands_read_file(path, satf_obj_parse, out, err);
}
