/* mesh.h - triangle meshes for rasterisation: the cluster layer meshes
 * (SATF sec. 6.1) and opaque meshes such as heads. A C front end to an
 * OpenMesh TriMesh (online/mesh_openmesh.cpp); the data is also kept as
 * plain arrays ready for a GL upload.
 *
 * Per vertex: position, unit normal, tangent (the hair direction on layer
 * meshes, zero on meshes read from files) and texture coordinates. Files
 * (OBJ, PLY) carry positions, normals and texture coordinates, not
 * tangents or layer_v. */
#ifndef SATF_MESH_H
#define SATF_MESH_H

#include <stddef.h>
#include <stdint.h>

#include "satf/satf.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct satf_mesh satf_mesh;

/* Interleaved vertex, 44 bytes, in the order of the GL attributes. */
typedef struct satf_mesh_vertex {
  float pos[3];
  float normal[3];
  float tangent[3];
  float uv[2];
} satf_mesh_vertex;

typedef struct satf_mesh_desc {
  size_t n_vertices;
  const float *positions; /* 3 per vertex, required */
  const float *normals;   /* 3 per vertex; NULL: computed from the faces */
  const float *tangents;  /* 3 per vertex; NULL: zero */
  const float *uvs;       /* 2 per vertex; NULL: zero */
  size_t n_triangles;
  const uint32_t *indices; /* 3 per triangle, counter-clockwise seen from
                              the side the normal points to */
  float layer_v;           /* the shell radius v of a layer mesh, or -1 */
} satf_mesh_desc;

/* Copies desc into a new mesh. Rejects out-of-range indices, non-finite
 * positions, and triangles OpenMesh cannot add (repeated vertices or
 * non-manifold edges). */
satf_status satf_mesh_create(const satf_mesh_desc *desc, satf_mesh **out,
                             satf_error *err);
/* As satf_mesh_create, for a desc whose triangles are exactly those of
 * `topology` (checked): the OpenMesh connectivity is copied instead of
 * rebuilt triangle by triangle, several times faster. Meant for the layer
 * meshes, which all share one grid. */
satf_status satf_mesh_create_with_topology(const satf_mesh *topology,
                                           const satf_mesh_desc *desc,
                                           satf_mesh **out, satf_error *err);
void satf_mesh_destroy(satf_mesh *mesh);

/* Recomputes vertex normals with OpenMesh (each the normalised sum of its
 * faces' normals). Vertices at exactly the same position, such as the
 * duplicated u seam of a layer mesh, then share their averaged normal so
 * seams do not show in the shading. */
satf_status satf_mesh_update_normals(satf_mesh *mesh, satf_error *err);

size_t satf_mesh_vertex_count(const satf_mesh *mesh);
size_t satf_mesh_triangle_count(const satf_mesh *mesh);
/* satf_mesh_vertex_count entries, valid until the mesh changes. */
const satf_mesh_vertex *satf_mesh_vertices(const satf_mesh *mesh);
/* 3 * satf_mesh_triangle_count entries. */
const uint32_t *satf_mesh_indices(const satf_mesh *mesh);
/* The layer's v (see satf_mesh_desc), -1 for meshes read from files. */
float satf_mesh_layer_v(const satf_mesh *mesh);
/* Axis-aligned bounds of the positions (zeros for an empty mesh). */
void satf_mesh_bounds(const satf_mesh *mesh, float lo[3], float hi[3]);

/* Writes an OBJ or a binary PLY chosen by the extension of path (.obj,
 * .ply, any case), with normals and texture coordinates, through a
 * temporary file renamed into place. */
satf_status satf_mesh_write(const satf_mesh *mesh, const char *path,
                            satf_error *err);
/* Reads an OBJ or PLY (ASCII or binary); polygons are triangulated. Normals
 * come from the file when present, else from satf_mesh_update_normals. */
satf_status satf_mesh_read(const char *path, satf_mesh **out, satf_error *err);

#ifdef __cplusplus
}
#endif
#endif
