/* strands_ply.h - the PLY reader's parts (strands_ply*.c): the header, a
 * cursor over the body that reads one property value at a time in any of
 * the three encodings, and the strand builders. Private to satf_import. */
#ifndef SATF_IMPORT_STRANDS_PLY_H
#define SATF_IMPORT_STRANDS_PLY_H

#include <stddef.h>
#include <stdint.h>

#include "satf/common.h"
#include "satf/import.h"

enum { PLY_ASCII, PLY_LE, PLY_BE };
enum { PLY_MAX_ELEMENTS = 16, PLY_MAX_PROPS = 32, PLY_MAX_NAME = 32 };

typedef struct ply_property {
  char name[PLY_MAX_NAME];
  int type;    /* index into the type table of strands_ply_header.c */
  int is_list; /* then count_type is the type of the list's length */
  int count_type;
} ply_property;

typedef struct ply_element {
  char name[PLY_MAX_NAME];
  uint64_t count;
  int n_props;
  ply_property props[PLY_MAX_PROPS];
} ply_element;

typedef struct ply_header {
  int format;
  int n_elements;
  ply_element elements[PLY_MAX_ELEMENTS];
} ply_header;

typedef struct ply_cursor {
  const unsigned char *p, *end;
  int format;
  const char *name;
  char why[128]; /* what went wrong when a read returns -1 */
} ply_cursor;

/* Parses the header and checks every element's count against the bytes
 * after it (each record needs at least its minimal encoded size), so a
 * caller may allocate by the counts. c is left at the body. */
satf_status ply_parse_header(const void *data, size_t size, const char *name,
                             ply_header *h, ply_cursor *c, satf_error *err);

/* Reads one property value (a list's values are read and dropped: *out is
 * then its length). Returns -1 with c->why set at the end of the data or
 * on a malformed value. */
int ply_read_prop(ply_cursor *c, const ply_property *p, double *out);
int ply_skip_element(ply_cursor *c, const ply_element *e);

/* Strands of counts[i] points (+1 with plus_one: segment counts) taken in
 * vertex order; counts must add up to n_vertices. Single points are
 * skipped. */
satf_status ply_strands_from_counts(const char *name, const float *xyz,
                                    uint64_t n_vertices, const int64_t *counts,
                                    uint64_t n_strands, int plus_one,
                                    satf_strand_set **out, satf_error *err);

/* Strands chained from n_edges vertex index pairs (edges[2 * k], edges[2 *
 * k + 1]): every vertex has at most two edges; each chain runs from its
 * lower-numbered end; loops are refused. rgb (3 a vertex, or NULL): the
 * vertices' colours, kept on the strands' points. */
satf_status ply_strands_from_edges(const char *name, const float *xyz,
                                   const float *rgb, uint64_t n_vertices,
                                   const int64_t *edges, uint64_t n_edges,
                                   satf_strand_set **out, satf_error *err);

#endif
