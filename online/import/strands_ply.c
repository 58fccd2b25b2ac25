/* strands_ply.c - strand hair in PLY files as research tools write them:
 * a `vertex` element with x, y, z (other properties, such as colours, are
 * skipped) and either
 *   - a strand element (named `strand`, `strands`, `hair` or `curve`) with
 *     one integer per strand: its point count (property `vertex_count`,
 *     `vertices`, `num_vertices`, `nverts`, `num_points`, `points` or
 *     `count`) or its segment count (`segments`, `num_segments`,
 *     `segment_count`, `nsegs`, `num_segs`: one point more), the strands'
 *     points following each other in vertex order; or
 *   - an `edge` element of vertex index pairs (`vertex1`, `vertex2`, as
 *     MeshLab and Blender write them), chained into polylines: each chain
 *     runs from its lower-numbered end.
 * Formats ascii, binary_little_endian and binary_big_endian. Strands of a
 * single point are skipped; branching or looping edges are refused. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "satf/import.h"
#include "strands_ply.h"
#include "strands_read.h"

static const char *const COUNT_NAMES[] = {
    "vertex_count", "vertices", "num_vertices", "nverts",
    "num_points",   "points",   "count",        NULL};
static const char *const SEGMENT_NAMES[] = {
    "segments", "num_segments", "segment_count", "nsegs", "num_segs", NULL};
static const char *const STRAND_ELEMENTS[] = {"strand", "strands", "hair",
                                              "curve", NULL};

static int in_list(const char *s, const char *const *list) {
  for (int i = 0; list[i]; i++)
    if (strcmp(s, list[i]) == 0)
      return 1;
  return 0;
}

static int prop_find(const ply_element *e, const char *name) {
  for (int p = 0; p < e->n_props; p++)
    if (!e->props[p].is_list && strcmp(e->props[p].name, name) == 0)
      return p;
  return -1;
}

/* The vertex positions into xyz (3 per vertex). */
static satf_status read_vertices(ply_cursor *c, const ply_element *e,
                                 float *xyz, satf_error *err) {
  int ix = prop_find(e, "x"), iy = prop_find(e, "y"), iz = prop_find(e, "z");
  for (uint64_t v = 0; v < e->count; v++)
    for (int p = 0; p < e->n_props; p++) {
      double val;
      if (ply_read_prop(c, &e->props[p], &val) != 0)
        return satf_error_set(err, SATF_ERR_CORRUPT, "%s: vertex %llu: %s",
                              c->name, (unsigned long long)v, c->why);
      int axis = p == ix ? 0 : p == iy ? 1 : p == iz ? 2 : -1;
      if (axis < 0)
        continue;
      xyz[3 * v + (uint64_t)axis] = (float)val;
      if (!isfinite(xyz[3 * v + (uint64_t)axis]))
        return satf_error_set(err, SATF_ERR_CORRUPT,
                              "%s: vertex %llu: coordinate %c is not a "
                              "finite float",
                              c->name, (unsigned long long)v, "xyz"[axis]);
    }
  return SATF_OK;
}

/* One integer per record of e (property `which`) into out[count]. */
static satf_status read_ints(ply_cursor *c, const ply_element *e, int which,
                             int64_t *out, satf_error *err) {
  for (uint64_t r = 0; r < e->count; r++)
    for (int p = 0; p < e->n_props; p++) {
      double val;
      if (ply_read_prop(c, &e->props[p], &val) != 0)
        return satf_error_set(err, SATF_ERR_CORRUPT, "%s: %s %llu: %s", c->name,
                              e->name, (unsigned long long)r, c->why);
      if (p != which && !(which < 0 && p < 2))
        continue;
      if (!(val >= -2147483648.0 && val <= 2147483647.0) || val != floor(val))
        return satf_error_set(
            err, SATF_ERR_CORRUPT, "%s: %s %llu: %s is %g, not an integer",
            c->name, e->name, (unsigned long long)r, e->props[p].name, val);
      out[which < 0 ? 2 * r + (uint64_t)p : r] = (int64_t)val;
    }
  return SATF_OK;
}

/* What the header says about the strands: which element holds them. */
typedef struct ply_plan {
  int vertex, strand, edge; /* element indices, -1: absent */
  int count_prop, plus;     /* strand element's property; +1 for segments */
  int e1, e2;               /* edge element's vertex properties */
} ply_plan;

static satf_status plan_vertex(const char *name, const ply_header *h,
                               ply_plan *pl, satf_error *err) {
  if (pl->vertex < 0)
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: no `vertex` element: no points", name);
  const ply_element *v = &h->elements[pl->vertex];
  static const char *const axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; a++)
    if (prop_find(v, axes[a]) < 0)
      return satf_error_set(err, SATF_ERR_FORMAT,
                            "%s: the vertex element has no scalar property "
                            "`%s`",
                            name, axes[a]);
  if (v->count == 0)
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: holds no vertices", name);
  if (v->count > SATF_STRANDS_MAX_POINTS)
    return satf_error_set(
        err, SATF_ERR_CORRUPT, "%s: absurd vertex count %llu (at most %u)",
        name, (unsigned long long)v->count, SATF_STRANDS_MAX_POINTS);
  return SATF_OK;
}

static satf_status plan_strands(const char *name, const ply_header *h,
                                ply_plan *pl, satf_error *err) {
  memset(pl, -1, sizeof *pl);
  pl->plus = 0;
  for (int i = 0; i < h->n_elements; i++) {
    const char *en = h->elements[i].name;
    if (strcmp(en, "vertex") == 0 && pl->vertex < 0)
      pl->vertex = i;
    else if (in_list(en, STRAND_ELEMENTS) && pl->strand < 0)
      pl->strand = i;
    else if (strcmp(en, "edge") == 0 && pl->edge < 0)
      pl->edge = i;
  }
  /* an element of another name whose property is a count is the strands'
   * too (writers name it as they like; the property names are the sign) */
  for (int i = 0; i < h->n_elements && pl->strand < 0; i++) {
    const ply_element *e = &h->elements[i];
    if (i == pl->vertex || i == pl->edge || strcmp(e->name, "face") == 0)
      continue;
    for (int p = 0; p < e->n_props; p++)
      if (!e->props[p].is_list && (in_list(e->props[p].name, SEGMENT_NAMES) ||
                                   in_list(e->props[p].name, COUNT_NAMES)))
        pl->strand = i;
  }
  satf_status st = plan_vertex(name, h, pl, err);
  if (st != SATF_OK)
    return st;
  if (pl->strand >= 0) {
    const ply_element *s = &h->elements[pl->strand];
    for (int p = 0; p < s->n_props && pl->count_prop < 0; p++) {
      int seg = in_list(s->props[p].name, SEGMENT_NAMES);
      if (!s->props[p].is_list &&
          (seg || in_list(s->props[p].name, COUNT_NAMES))) {
        pl->count_prop = p;
        pl->plus = seg;
      }
    }
    if (pl->count_prop >= 0)
      return SATF_OK;
    if (pl->edge < 0)
      return satf_error_set(err, SATF_ERR_FORMAT,
                            "%s: the `%s` element has no point count "
                            "property (vertex_count, vertices, num_vertices, "
                            "nverts, num_points, points, count) nor a "
                            "segment count (segments, num_segments, "
                            "segment_count, nsegs, num_segs)",
                            name, s->name);
    pl->strand = -1; /* no counts: the edges say which points join */
  }
  if (pl->edge >= 0) {
    const ply_element *e = &h->elements[pl->edge];
    pl->e1 = prop_find(e, "vertex1");
    pl->e2 = prop_find(e, "vertex2");
    if (pl->e1 != 0 || pl->e2 != 1)
      return satf_error_set(err, SATF_ERR_FORMAT,
                            "%s: the `edge` element must start with the "
                            "scalar properties vertex1 and vertex2",
                            name);
    return SATF_OK;
  }
  return satf_error_set(err, SATF_ERR_FORMAT,
                        "%s: vertices but neither a strand element (strand, "
                        "strands, hair, curve) nor an `edge` element: "
                        "nothing says which points form a strand",
                        name);
}

/* Reads every element in file order, keeping the vertices and the strand
 * counts or edges the plan names. */
static satf_status read_body(ply_cursor *c, const ply_header *h,
                             const ply_plan *pl, float *xyz, int64_t *ints,
                             satf_error *err) {
  satf_status st = SATF_OK;
  for (int i = 0; i < h->n_elements && st == SATF_OK; i++) {
    const ply_element *e = &h->elements[i];
    if (i == pl->vertex)
      st = read_vertices(c, e, xyz, err);
    else if (i == pl->strand)
      st = read_ints(c, e, pl->count_prop, ints, err);
    else if (i == pl->edge && pl->strand < 0)
      st = read_ints(c, e, -1, ints, err);
    else if (ply_skip_element(c, e) != 0)
      st = satf_error_set(err, SATF_ERR_CORRUPT, "%s: element `%s`: %s",
                          c->name, e->name, c->why);
  }
  return st;
}

satf_status satf_ply_parse(const void *data, size_t size, const char *name,
                           satf_strand_set **out, satf_error *err) {
  *out = NULL;
  if (!name)
    name = "<ply>";
  ply_header h;
  ply_cursor c;
  satf_status st = ply_parse_header(data, size, name, &h, &c, err);
  ply_plan pl;
  if (st == SATF_OK)
    st = plan_strands(name, &h, &pl, err);
  if (st != SATF_OK)
    return st;
  /* every count was checked against the bytes left by ply_parse_header */
  uint64_t nv = h.elements[pl.vertex].count;
  uint64_t ni = pl.strand >= 0 ? h.elements[pl.strand].count
                               : 2 * h.elements[pl.edge].count;
  float *xyz = malloc(3 * nv * sizeof(float));
  int64_t *ints = malloc((ni ? ni : 1) * sizeof(int64_t));
  if (!xyz || !ints)
    st = satf_error_set(err, SATF_ERR_NOMEM, "%s: cannot hold %llu vertices",
                        name, (unsigned long long)nv);
  if (st == SATF_OK)
    st = read_body(&c, &h, &pl, xyz, ints, err);
  if (st == SATF_OK)
    st = pl.strand >= 0 ? ply_strands_from_counts(name, xyz, nv, ints, ni,
                                                  pl.plus, out, err)
                        : ply_strands_from_edges(name, xyz, NULL, nv, ints,
                                                 ni / 2, out, err);
  free(xyz);
  free(ints);
  return st;
}

satf_status satf_ply_read(const char *path, satf_strand_set **out,
                          satf_error *err) {
  return strands_read_file(path, satf_ply_parse, out, err);
}
