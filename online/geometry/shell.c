/* shell.c - the layered shells of a cluster (SATF sec. 3.2, eq. 3): layer
 * radii, the HSV partition, boundary generalized sectors and the layer
 * meshes (SATF sec. 6.1). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "satf/geometry.h"

#define SHELL_MAX_LAYERS 256
#define SHELL_MAX_ST 4096
#define SHELL_MAX_SU 4096
#define SHELL_MAX_CORE 0.95f
/* Beyond this many HSVs the per-HSV maps could not be built in any frame. */
#define SHELL_MAX_HSVS ((size_t)1 << 26)

static const double kTwoPi = 6.283185307179586476925286766559;

satf_status satf_shell_params_check(const satf_shell_params *p,
                                    satf_error *err) {
  if (!p)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "shell: params is NULL");
  if (p->layers < 1 || p->layers > SHELL_MAX_LAYERS)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "shell/layers: %d, need 1..%d", p->layers,
                          SHELL_MAX_LAYERS);
  if (p->st < 1 || p->st > SHELL_MAX_ST)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "shell/st: %d, need 1..%d",
                          p->st, SHELL_MAX_ST);
  if (p->su < 3 || p->su > SHELL_MAX_SU)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "shell/su: %d, need 3..%d",
                          p->su, SHELL_MAX_SU);
  if (!(p->core >= 0.0f && p->core <= SHELL_MAX_CORE))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "shell/core: %g, need a v radius in [0, %g]",
                          (double)p->core, (double)SHELL_MAX_CORE);
  size_t count = (size_t)p->st * (size_t)p->layers * (size_t)p->su;
  if (count > SHELL_MAX_HSVS)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "shell: st * layers * su = %zu HSVs exceeds %zu",
                          count, SHELL_MAX_HSVS);
  return SATF_OK;
}

size_t satf_shell_hsv_count(const satf_shell_params *params) {
  if (satf_shell_params_check(params, NULL))
    return 0;
  return (size_t)params->st * (size_t)params->layers * (size_t)params->su;
}

size_t satf_shell_hsv_index(const satf_shell_params *params, int i, int k,
                            int j) {
  return ((size_t)i * (size_t)params->layers + (size_t)k) * (size_t)params->su +
         (size_t)j;
}

/* v_j = core + (1 - core) j / layers: the shell is split evenly in v
 * (SATF eq. 3, step 1/sv within the shell). */
float satf_shell_layer_v(const satf_shell_params *params, int j) {
  if (j >= params->layers)
    return 1.0f; /* exact, whatever the rounding of core */
  return params->core +
         (1.0f - params->core) * (float)j / (float)params->layers;
}

/* Phase of sample j around the cluster: u_j = 2 pi j / su (SATF eq. 3). */
static float phase_u(const satf_shell_params *params, int j) {
  return (float)(kTwoPi * (double)j / (double)params->su);
}

/* t_i = i / st (SATF eq. 3). */
static float sample_t(const satf_shell_params *params, int i) {
  return (float)i / (float)params->st;
}

static void copy3(const float in[3], float out[3]) {
  out[0] = in[0];
  out[1] = in[1];
  out[2] = in[2];
}

satf_status satf_shell_sector_at(const satf_cluster *cluster,
                                 const satf_shell_params *params, int i, int k,
                                 int j, satf_shell_sector *out,
                                 satf_error *err) {
  if (!cluster || !out)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "shell sector: cluster or out is NULL");
  satf_status st = satf_shell_params_check(params, err);
  if (st)
    return st;
  if (i < 0 || i > params->st || k < 0 || k >= params->layers || j < 0 ||
      j >= params->su)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "shell sector: (i, k, j) = (%d, %d, %d) outside "
                          "[0,%d] x [0,%d) x [0,%d)",
                          i, k, j, params->st, params->layers, params->su);
  satf_cluster_section s;
  satf_cluster_section_at(cluster, sample_t(params, i), &s);
  out->t = s.t;
  out->layer = k;
  out->phase = j;
  out->v_inner = satf_shell_layer_v(params, k);
  out->v_outer = satf_shell_layer_v(params, k + 1);
  out->u_begin = phase_u(params, j);
  out->u_end = phase_u(params, j + 1);
  out->a = s.a;
  out->b = s.b;
  satf_cluster_section_point(&s, out->v_inner, out->u_begin, out->corners[0]);
  satf_cluster_section_point(&s, out->v_outer, out->u_begin, out->corners[1]);
  satf_cluster_section_point(&s, out->v_outer, out->u_end, out->corners[2]);
  satf_cluster_section_point(&s, out->v_inner, out->u_end, out->corners[3]);
  copy3(s.center, out->origin);
  copy3(s.tangent, out->normal);
  copy3(s.rmf_n1, out->n1);
  copy3(s.rmf_n2, out->n2);
  out->theta = s.theta;
  /* the section's axes are already turned by theta (SATF eq. 1 as
   * satf/geometry.h reads it), so the sector's phase u starts on them */
  copy3(s.n1, out->axis_x);
  copy3(s.n2, out->axis_y);
  return SATF_OK;
}

satf_status satf_shell_hsv_sectors(const satf_cluster *cluster,
                                   const satf_shell_params *params, int i,
                                   int k, int j, satf_shell_sector out[2],
                                   satf_error *err) {
  if (params && (i < 0 || i >= params->st))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "shell hsv: i = %d outside [0,%d)", i, params->st);
  satf_status st = satf_shell_sector_at(cluster, params, i, k, j, &out[0], err);
  if (st)
    return st;
  return satf_shell_sector_at(cluster, params, i + 1, k, j, &out[1], err);
}

/* ---- layer meshes ---- */

typedef struct layer_arrays {
  float *pos, *tan, *uv;
  uint32_t *idx;
} layer_arrays;

static void free_layer_arrays(layer_arrays *a) {
  free(a->pos);
  free(a->tan);
  free(a->uv);
  free(a->idx);
}

/* Vertex (i, j) of the (st + 1) x (su + 1) grid. */
static uint32_t grid_vertex(const satf_shell_params *p, int i, int j) {
  return (uint32_t)i * (uint32_t)(p->su + 1) + (uint32_t)j;
}

/* Positions, hair tangents and uv on the surface v of ring i. Column su
 * repeats column 0 exactly so the seam closes without a crack. */
static void fill_ring(const satf_cluster *cl, const satf_shell_params *p,
                      float v, int i, layer_arrays *a) {
  satf_cluster_section s;
  satf_cluster_section_at(cl, sample_t(p, i), &s);
  for (int j = 0; j <= p->su; j++) {
    size_t n = grid_vertex(p, i, j);
    size_t src = grid_vertex(p, i, 0);
    if (j < p->su) {
      float u = phase_u(p, j);
      satf_cluster_section_point(&s, v, u, a->pos + 3 * n);
      satf_cluster_section_hair_tangent(&s, v, u, a->tan + 3 * n);
    } else {
      copy3(a->pos + 3 * src, a->pos + 3 * n);
      copy3(a->tan + 3 * src, a->tan + 3 * n);
    }
    a->uv[2 * n] = (float)j / (float)p->su;
    a->uv[2 * n + 1] = s.t;
  }
}

/* Two triangles per grid cell, wound so that (dP/du x dP/dt), the outward
 * direction for the right-handed frame (tangent, n1, n2), is their front. */
static void fill_indices(const satf_shell_params *p, uint32_t *idx) {
  size_t f = 0;
  for (int i = 0; i < p->st; i++)
    for (int j = 0; j < p->su; j++) {
      uint32_t a = grid_vertex(p, i, j), b = grid_vertex(p, i, j + 1);
      uint32_t c = grid_vertex(p, i + 1, j), d = grid_vertex(p, i + 1, j + 1);
      uint32_t tri[6] = {a, b, c, b, d, c};
      for (int q = 0; q < 6; q++)
        idx[f++] = tri[q];
    }
}

satf_status satf_cluster_build_layer_mesh(const satf_cluster *cluster,
                                          const satf_shell_params *params,
                                          int k, satf_mesh **out,
                                          satf_error *err) {
  return satf_cluster_build_layer_mesh_from(cluster, params, k, NULL, out, err);
}

satf_status satf_cluster_build_layer_mesh_from(const satf_cluster *cluster,
                                               const satf_shell_params *params,
                                               int k, const satf_mesh *grid,
                                               satf_mesh **out,
                                               satf_error *err) {
  if (!cluster || !out)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "layer mesh: cluster or out is NULL");
  *out = NULL;
  satf_status st = satf_shell_params_check(params, err);
  if (st)
    return st;
  if (k < 0 || k >= params->layers)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "layer mesh: layer %d outside [0,%d)", k,
                          params->layers);
  size_t nv = (size_t)(params->st + 1) * (size_t)(params->su + 1);
  size_t nf = 2 * (size_t)params->st * (size_t)params->su;
  layer_arrays a = {
      malloc(sizeof(float) * 3 * nv), malloc(sizeof(float) * 3 * nv),
      malloc(sizeof(float) * 2 * nv), malloc(sizeof(uint32_t) * 3 * nf)};
  if (!a.pos || !a.tan || !a.uv || !a.idx) {
    free_layer_arrays(&a);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "layer mesh: cannot allocate %zu vertices", nv);
  }
  float v = satf_shell_layer_v(params, k + 1); /* the outer surface */
  for (int i = 0; i <= params->st; i++)
    fill_ring(cluster, params, v, i, &a);
  fill_indices(params, a.idx);
  satf_mesh_desc desc = {.n_vertices = nv,
                         .positions = a.pos,
                         .normals = NULL, /* OpenMesh computes them */
                         .tangents = a.tan,
                         .uvs = a.uv,
                         .n_triangles = nf,
                         .indices = a.idx,
                         .layer_v = v};
  st = grid ? satf_mesh_create_with_topology(grid, &desc, out, err)
            : satf_mesh_create(&desc, out, err);
  free_layer_arrays(&a);
  return st;
}
