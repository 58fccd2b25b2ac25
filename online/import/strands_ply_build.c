/* strands_ply_build.c - a PLY file's vertices made strands: by per-strand
 * point counts, or by chaining edges into polylines. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "strands_ply.h"

/* The strand set of kept strands, with the file named in its errors. */
static satf_status make_set(const char *name, int n, const int *counts,
                            const float *pts, const float *rgb,
                            satf_strand_set **out, satf_error *err) {
  if (n == 0)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: holds no strand of two or more points", name);
  satf_error why;
  if (satf_strand_set_create(n, counts, pts, NULL, out, &why) != SATF_OK ||
      (rgb && satf_strand_set_add_colour(*out, rgb, &why) != SATF_OK)) {
    satf_strand_set_destroy(*out);
    *out = NULL;
    return satf_error_set(err, why.status, "%s: %s", name, why.message);
  }
  return SATF_OK;
}

satf_status ply_strands_from_counts(const char *name, const float *xyz,
                                    uint64_t n_vertices, const int64_t *counts,
                                    uint64_t n_strands, int plus_one,
                                    satf_strand_set **out, satf_error *err) {
  *out = NULL;
  if (n_strands == 0)
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: holds no strands", name);
  if (n_strands > SATF_STRANDS_MAX_STRANDS)
    return satf_error_set(
        err, SATF_ERR_CORRUPT, "%s: absurd strand count %llu (at most %u)",
        name, (unsigned long long)n_strands, SATF_STRANDS_MAX_STRANDS);
  uint64_t sum = 0;
  for (uint64_t i = 0; i < n_strands; i++) {
    int64_t n = counts[i] + plus_one;
    if (n < 0 || n > SATF_STRANDS_MAX_PER_STRAND)
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: strand %llu has an absurd %lld points (at "
                            "most %d)",
                            name, (unsigned long long)i, (long long)n,
                            SATF_STRANDS_MAX_PER_STRAND);
    sum += (uint64_t)n;
  }
  if (sum != n_vertices)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: counts do not add up: the strands need %llu "
                          "points, the file has %llu vertices",
                          name, (unsigned long long)sum,
                          (unsigned long long)n_vertices);
  int *kept = malloc(n_strands * sizeof(int));
  float *pts = malloc(3 * n_vertices * sizeof(float));
  if (!kept || !pts) {
    free(kept);
    free(pts);
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", name);
  }
  int n_kept = 0;
  size_t at = 0, to = 0;
  for (uint64_t i = 0; i < n_strands; i++) {
    size_t n = (size_t)(counts[i] + plus_one);
    if (n >= 2) { /* single points (roots without hair) are skipped */
      kept[n_kept++] = (int)n;
      memcpy(pts + 3 * to, xyz + 3 * at, 3 * n * sizeof(float));
      to += n;
    }
    at += n;
  }
  satf_status st = make_set(name, n_kept, kept, pts, NULL, out, err);
  free(kept);
  free(pts);
  return st;
}

/* Adjacency (two slots per vertex) of the edges, refusing branches. */
static satf_status link_edges(const char *name, uint64_t nv,
                              const int64_t *edges, uint64_t n_edges,
                              int64_t *adj, satf_error *err) {
  for (uint64_t v = 0; v < 2 * nv; v++)
    adj[v] = -1;
  for (uint64_t k = 0; k < n_edges; k++) {
    int64_t a = edges[2 * k], b = edges[2 * k + 1];
    if (a < 0 || b < 0 || (uint64_t)a >= nv || (uint64_t)b >= nv || a == b)
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: edge %llu joins vertices %lld and %lld (the "
                            "file has %llu vertices)",
                            name, (unsigned long long)k, (long long)a,
                            (long long)b, (unsigned long long)nv);
    int64_t ends[2] = {a, b};
    for (int e = 0; e < 2; e++) {
      int64_t *slot = adj + 2 * ends[e];
      int s = slot[0] < 0 ? 0 : slot[1] < 0 ? 1 : -1;
      if (s < 0)
        return satf_error_set(err, SATF_ERR_CORRUPT,
                              "%s: vertex %lld has more than two edges: "
                              "strands cannot branch",
                              name, (long long)ends[e]);
      slot[s] = ends[1 - e];
    }
  }
  return SATF_OK;
}

/* Walks every chain from its lower-numbered end into pts and counts (and
 * the vertices' colours into pts_rgb when rgb is not NULL). */
static satf_status walk_chains(const char *name, const float *xyz,
                               const float *rgb, uint64_t nv,
                               const int64_t *adj, unsigned char *seen,
                               float *pts, float *pts_rgb, int *counts,
                               int *n_strands, satf_error *err) {
  size_t to = 0;
  *n_strands = 0;
  for (uint64_t v = 0; v < nv; v++) {
    if (seen[v] || adj[2 * v] < 0 || adj[2 * v + 1] >= 0)
      continue; /* not an end, or an isolated point */
    int64_t prev = -1, cur = (int64_t)v;
    int n = 0;
    while (cur >= 0) {
      if (++n > SATF_STRANDS_MAX_PER_STRAND)
        return satf_error_set(err, SATF_ERR_CORRUPT,
                              "%s: the strand from vertex %llu has more than "
                              "%d points",
                              name, (unsigned long long)v,
                              SATF_STRANDS_MAX_PER_STRAND);
      seen[cur] = 1;
      if (rgb)
        memcpy(pts_rgb + 3 * to, rgb + 3 * cur, 3 * sizeof(float));
      memcpy(pts + 3 * to++, xyz + 3 * cur, 3 * sizeof(float));
      int64_t next = adj[2 * cur] != prev ? adj[2 * cur] : adj[2 * cur + 1];
      prev = cur;
      cur = next >= 0 && !seen[next] ? next : -1;
    }
    counts[(*n_strands)++] = n;
  }
  for (uint64_t v = 0; v < nv; v++)
    if (!seen[v] && adj[2 * v] >= 0)
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: the edges through vertex %llu form a loop, "
                            "not a strand",
                            name, (unsigned long long)v);
  return SATF_OK;
}

satf_status ply_strands_from_edges(const char *name, const float *xyz,
                                   const float *rgb, uint64_t n_vertices,
                                   const int64_t *edges, uint64_t n_edges,
                                   satf_strand_set **out, satf_error *err) {
  *out = NULL;
  if (n_edges == 0)
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: holds no edges", name);
  int64_t *adj = malloc(2 * n_vertices * sizeof *adj);
  unsigned char *seen = calloc(n_vertices, 1);
  float *pts = malloc(3 * n_vertices * sizeof(float));
  float *pts_rgb = rgb ? malloc(3 * n_vertices * sizeof(float)) : NULL;
  int *counts = malloc((n_vertices / 2 + 1) * sizeof(int));
  satf_status st = SATF_OK;
  if (!adj || !seen || !pts || !counts || (rgb && !pts_rgb))
    st = satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", name);
  int n = 0;
  if (st == SATF_OK)
    st = link_edges(name, n_vertices, edges, n_edges, adj, err);
  if (st == SATF_OK)
    st = walk_chains(name, xyz, rgb, n_vertices, adj, seen, pts, pts_rgb,
                     counts, &n, err);
  if (st == SATF_OK)
    st = make_set(name, n, counts, pts, pts_rgb, out, err);
  free(adj);
  free(seen);
  free(pts);
  free(pts_rgb);
  free(counts);
  return st;
}
