// mesh_openmesh.cpp - the OpenMesh shim behind satf/mesh.h. Owns the
// TriMesh (topology, normals, IO) and the flat arrays handed to GL; no C++
// exception crosses the C boundary.
#include "satf/geometry.h"

// OpenMesh's PropertyT::push_back appends a default-constructed VectorT,
// whose components are deliberately uninitialised; GCC flags that inside
// the template instantiated in this file. It is OpenMesh's idiom (the value
// is overwritten right after), not a bug here.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include <sys/stat.h>

extern "C" {
#include "satf/common.h"
}

namespace {

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

// Meshes beyond these sizes are a corrupt input, not a model.
constexpr size_t kMaxVertices = size_t(1) << 28;
constexpr size_t kMaxTriangles = size_t(1) << 29;

void quiet_openmesh() {
  // OpenMesh reports through process-wide log streams; library code must
  // not print, so they are switched off, once, race-free across threads.
  static std::once_flag once;
  std::call_once(once, [] {
    omlog().disable();
    omout().disable();
    omerr().disable();
  });
}

bool all_finite(const float *v, size_t n) {
  for (size_t i = 0; i < n; i++)
    if (!std::isfinite(v[i]))
      return false;
  return true;
}

} // namespace

struct satf_mesh {
  TriMesh om;
  std::vector<satf_mesh_vertex> verts;
  std::vector<uint32_t> indices;
  float layer_v = -1.0f;
};

namespace {

// Copies positions, normals and texture coordinates from the TriMesh into
// the flat vertex array (tangents stay as they are).
void pull_vertices(satf_mesh *m) {
  m->verts.resize(m->om.n_vertices());
  for (auto vh : m->om.vertices()) {
    satf_mesh_vertex &v = m->verts[vh.idx()];
    const auto &p = m->om.point(vh);
    const auto &n = m->om.normal(vh);
    const auto &uv = m->om.texcoord2D(vh);
    for (int c = 0; c < 3; c++) {
      v.pos[c] = p[c];
      v.normal[c] = n[c];
    }
    v.uv[0] = uv[0];
    v.uv[1] = uv[1];
  }
}

void pull_indices(satf_mesh *m) {
  m->indices.clear();
  m->indices.reserve(m->om.n_faces() * 3);
  for (auto fh : m->om.faces())
    for (auto vh : m->om.fv_range(fh))
      m->indices.push_back(uint32_t(vh.idx()));
}

// Vertices at identical positions get the normalised sum of their normals,
// so duplicated seam vertices shade alike.
void share_coincident_normals(satf_mesh *m) {
  struct Key {
    float p[3];
    uint32_t i;
  };
  const size_t n = m->verts.size();
  std::vector<Key> keys(n);
  for (size_t i = 0; i < n; i++) {
    std::memcpy(keys[i].p, m->verts[i].pos, sizeof keys[i].p);
    keys[i].i = uint32_t(i);
  }
  auto same = [](const Key &a, const Key &b) {
    return a.p[0] == b.p[0] && a.p[1] == b.p[1] && a.p[2] == b.p[2];
  };
  std::sort(keys.begin(), keys.end(), [](const Key &a, const Key &b) {
    return std::lexicographical_compare(a.p, a.p + 3, b.p, b.p + 3);
  });
  size_t begin = 0;
  while (begin < n) {
    size_t end = begin + 1;
    while (end < n && same(keys[begin], keys[end]))
      end++;
    if (end - begin > 1) {
      TriMesh::Normal sum(0.0f, 0.0f, 0.0f);
      for (size_t i = begin; i < end; i++)
        sum += m->om.normal(m->om.vertex_handle(int(keys[i].i)));
      if (sum.norm() > 0.0f)
        sum.normalize();
      for (size_t i = begin; i < end; i++)
        m->om.set_normal(m->om.vertex_handle(int(keys[i].i)), sum);
    }
    begin = end;
  }
}

void recompute_normals(satf_mesh *m) {
  m->om.update_face_normals();
  m->om.update_vertex_normals();
  m->verts.resize(m->om.n_vertices());
  // Coincidence is decided on the flat positions, so refresh them first.
  for (auto vh : m->om.vertices()) {
    const auto &p = m->om.point(vh);
    for (int c = 0; c < 3; c++)
      m->verts[vh.idx()].pos[c] = p[c];
  }
  share_coincident_normals(m);
  pull_vertices(m);
}

satf_mesh *new_mesh() {
  satf_mesh *m = new satf_mesh;
  m->om.request_face_normals();
  m->om.request_vertex_normals();
  m->om.request_vertex_texcoords2D();
  return m;
}

// Lower-case extension of path including the dot, or "".
std::string extension_of(const char *path) {
  const char *slash = std::strrchr(path, '/');
  const char *dot = std::strrchr(path, '.');
  if (!dot || (slash && dot < slash))
    return "";
  std::string ext(dot);
  for (char &c : ext)
    c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

satf_status check_desc(const satf_mesh_desc *d, satf_error *err) {
  if (!d)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "mesh: desc is NULL");
  if (d->n_vertices > kMaxVertices || d->n_triangles > kMaxTriangles)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "mesh: %zu vertices / %zu triangles exceed the "
                          "limits %zu / %zu",
                          d->n_vertices, d->n_triangles, kMaxVertices,
                          kMaxTriangles);
  if (d->n_vertices > 0 && !d->positions)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "mesh/positions: NULL");
  if (d->n_triangles > 0 && !d->indices)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "mesh/indices: NULL");
  if (d->n_vertices > 0 && !all_finite(d->positions, 3 * d->n_vertices))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "mesh/positions: a coordinate is not finite");
  if (d->normals && !all_finite(d->normals, 3 * d->n_vertices))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "mesh/normals: a component is not finite");
  for (size_t f = 0; f < d->n_triangles; f++) {
    const uint32_t *t = d->indices + 3 * f;
    for (int c = 0; c < 3; c++)
      if (t[c] >= d->n_vertices)
        return satf_error_set(err, SATF_ERR_ARGUMENT,
                              "mesh/indices: triangle %zu refers to vertex "
                              "%u of %zu",
                              f, t[c], d->n_vertices);
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "mesh/indices: triangle %zu repeats a vertex "
                            "(%u %u %u)",
                            f, t[0], t[1], t[2]);
  }
  return SATF_OK;
}

// Positions, texture coordinates, given normals and tangents of d on the
// vertices of m, adding the vertices when m has none yet.
void set_vertex_data(satf_mesh *m, const satf_mesh_desc *d) {
  const bool add = m->om.n_vertices() == 0;
  m->layer_v = d->layer_v;
  m->verts.assign(d->n_vertices, satf_mesh_vertex{});
  for (size_t i = 0; i < d->n_vertices; i++) {
    const float *p = d->positions + 3 * i;
    TriMesh::Point point(p[0], p[1], p[2]);
    TriMesh::VertexHandle vh;
    if (add) {
      vh = m->om.add_vertex(point);
    } else {
      vh = m->om.vertex_handle(int(i));
      m->om.set_point(vh, point);
    }
    TriMesh::TexCoord2D uv(0.0f, 0.0f);
    if (d->uvs)
      uv = TriMesh::TexCoord2D(d->uvs[2 * i], d->uvs[2 * i + 1]);
    m->om.set_texcoord2D(vh, uv);
    if (d->normals) {
      const float *n = d->normals + 3 * i;
      m->om.set_normal(vh, TriMesh::Normal(n[0], n[1], n[2]));
    }
    if (d->tangents)
      std::memcpy(m->verts[i].tangent, d->tangents + 3 * i, 3 * sizeof(float));
  }
}

void finish_normals(satf_mesh *m, const satf_mesh_desc *d) {
  if (d->normals) {
    m->om.update_face_normals();
    pull_vertices(m);
  } else {
    recompute_normals(m);
  }
}

satf_status fill_mesh(satf_mesh *m, const satf_mesh_desc *d, satf_error *err) {
  m->om.reserve(d->n_vertices, 3 * d->n_triangles, d->n_triangles);
  set_vertex_data(m, d);
  for (size_t f = 0; f < d->n_triangles; f++) {
    const uint32_t *t = d->indices + 3 * f;
    auto fh = m->om.add_face(m->om.vertex_handle(int(t[0])),
                             m->om.vertex_handle(int(t[1])),
                             m->om.vertex_handle(int(t[2])));
    if (!fh.is_valid())
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "mesh/indices: triangle %zu (%u %u %u) makes a "
                            "non-manifold edge or vertex",
                            f, t[0], t[1], t[2]);
  }
  // Keep the caller's index order (OpenMesh may start a face elsewhere).
  m->indices.assign(d->indices, d->indices + 3 * d->n_triangles);
  finish_normals(m, d);
  return SATF_OK;
}

satf_status check_same_topology(const satf_mesh *topology,
                                const satf_mesh_desc *d, satf_error *err) {
  if (d->n_vertices != topology->verts.size() ||
      3 * d->n_triangles != topology->indices.size())
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "mesh: %zu vertices / %zu triangles, but the "
                          "topology mesh has %zu / %zu",
                          d->n_vertices, d->n_triangles, topology->verts.size(),
                          topology->indices.size() / 3);
  if (d->n_triangles > 0 &&
      std::memcmp(d->indices, topology->indices.data(),
                  3 * d->n_triangles * sizeof(uint32_t)) != 0)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "mesh/indices: triangles differ from those of "
                          "the topology mesh");
  return SATF_OK;
}

} // namespace

extern "C" {

satf_status satf_mesh_create(const satf_mesh_desc *desc, satf_mesh **out,
                             satf_error *err) {
  if (!out)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "mesh: out is NULL");
  *out = nullptr;
  satf_status st = check_desc(desc, err);
  if (st)
    return st;
  quiet_openmesh();
  satf_mesh *m = nullptr;
  try {
    m = new_mesh();
    st = fill_mesh(m, desc, err);
  } catch (const std::bad_alloc &) {
    st = satf_error_set(err, SATF_ERR_NOMEM,
                        "mesh: out of memory for %zu vertices",
                        desc->n_vertices);
  } catch (const std::exception &e) {
    st = satf_error_set(err, SATF_ERR_INTERNAL, "mesh: OpenMesh: %s", e.what());
  }
  if (st) {
    delete m;
    return st;
  }
  *out = m;
  return SATF_OK;
}

satf_status satf_mesh_create_with_topology(const satf_mesh *topology,
                                           const satf_mesh_desc *desc,
                                           satf_mesh **out, satf_error *err) {
  if (!out || !topology)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "mesh: out or topology is NULL");
  *out = nullptr;
  satf_status st = check_desc(desc, err);
  if (st || (st = check_same_topology(topology, desc, err)))
    return st;
  quiet_openmesh();
  satf_mesh *m = nullptr;
  try {
    m = new satf_mesh;
    m->om = topology->om; // connectivity and attribute arrays, deep copy
    m->indices = topology->indices;
    set_vertex_data(m, desc);
    finish_normals(m, desc);
  } catch (const std::bad_alloc &) {
    delete m;
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "mesh: out of memory for %zu vertices",
                          desc->n_vertices);
  } catch (const std::exception &e) {
    delete m;
    return satf_error_set(err, SATF_ERR_INTERNAL, "mesh: OpenMesh: %s",
                          e.what());
  }
  *out = m;
  return SATF_OK;
}

void satf_mesh_destroy(satf_mesh *mesh) { delete mesh; }

satf_status satf_mesh_update_normals(satf_mesh *mesh, satf_error *err) {
  if (!mesh)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "mesh: handle is NULL");
  try {
    recompute_normals(mesh);
  } catch (const std::bad_alloc &) {
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "mesh: out of memory updating normals");
  }
  return SATF_OK;
}

size_t satf_mesh_vertex_count(const satf_mesh *mesh) {
  return mesh->verts.size();
}

size_t satf_mesh_triangle_count(const satf_mesh *mesh) {
  return mesh->indices.size() / 3;
}

const satf_mesh_vertex *satf_mesh_vertices(const satf_mesh *mesh) {
  return mesh->verts.data();
}

const uint32_t *satf_mesh_indices(const satf_mesh *mesh) {
  return mesh->indices.data();
}

float satf_mesh_layer_v(const satf_mesh *mesh) { return mesh->layer_v; }

void satf_mesh_bounds(const satf_mesh *mesh, float lo[3], float hi[3]) {
  for (int c = 0; c < 3; c++)
    lo[c] = hi[c] = mesh->verts.empty() ? 0.0f : mesh->verts[0].pos[c];
  for (const satf_mesh_vertex &v : mesh->verts)
    for (int c = 0; c < 3; c++) {
      lo[c] = std::min(lo[c], v.pos[c]);
      hi[c] = std::max(hi[c], v.pos[c]);
    }
}

satf_status satf_mesh_write(const satf_mesh *mesh, const char *path,
                            satf_error *err) {
  if (!mesh || !path)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "mesh write: mesh or path is NULL");
  std::string ext = extension_of(path);
  if (ext != ".obj" && ext != ".ply")
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: unknown mesh extension '%s' (use .obj or "
                          ".ply)",
                          path, ext.c_str());
  quiet_openmesh();
  char tmp[4096];
  satf_status st = satf_temp_path(path, tmp, sizeof tmp, err);
  if (st)
    return st;
  OpenMesh::IO::Options opt = OpenMesh::IO::Options::VertexNormal |
                              OpenMesh::IO::Options::VertexTexCoord;
  if (ext == ".ply")
    opt += OpenMesh::IO::Options::Binary;
  bool ok = false;
  try {
    std::ofstream os(tmp, std::ios::binary | std::ios::trunc);
    // 9 significant digits round-trip a float exactly in ASCII formats.
    ok = os.good() && OpenMesh::IO::write_mesh(mesh->om, os, ext, opt, 9);
    os.close();
    ok = ok && !os.fail();
  } catch (...) {
    ok = false;
  }
  if (!ok) {
    std::remove(tmp);
    return satf_error_set(err, SATF_ERR_IO,
                          "%s: OpenMesh could not write "
                          "the mesh",
                          path);
  }
  return satf_commit_temp(tmp, path, err);
}

/* The number of faces the file declares: PLY's "element face N" header
 * line, or OBJ's "f" lines. OpenMesh skips a face it cannot use (a vertex
 * index out of range, a non-manifold edge) and still reports success, so
 * the count is how a dropped face is noticed. -1 when it cannot be told. */
static long long declared_faces(const char *path, const std::string &ext) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  long long n = 0;
  if (ext == ".ply") {
    while (std::getline(in, line) && line.rfind("end_header", 0) != 0) {
      long long v = 0;
      if (std::sscanf(line.c_str(), "element face %lld", &v) == 1)
        return v;
    }
    return -1;
  }
  while (std::getline(in, line))
    if (line.size() > 1 && line[0] == 'f' &&
        std::isspace((unsigned char)line[1]))
      n++;
  return n;
}

/* A mesh that satf can use: faces exist, none was dropped, every vertex
 * is finite. */
static satf_status check_read_mesh(const char *path, const std::string &ext,
                                   const satf_mesh *m, satf_error *err) {
  size_t faces = m->om.n_faces();
  if (faces == 0)
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: no faces (an empty file, or not a mesh)", path);
  long long declared = declared_faces(path, ext);
  if (declared > 0 && (long long)faces < declared)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: %lld of %lld faces could not be used (vertex "
                          "indices out of range, or non-manifold edges)",
                          path, declared - (long long)faces, declared);
  for (const satf_mesh_vertex &v : m->verts)
    if (!all_finite(v.pos, 3))
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: a vertex position is not finite", path);
  return SATF_OK;
}

satf_status satf_mesh_read(const char *path, satf_mesh **out, satf_error *err) {
  if (!out || !path)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "mesh read: out or path is NULL");
  *out = nullptr;
  std::string ext = extension_of(path);
  if (ext != ".obj" && ext != ".ply")
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: unknown mesh extension '%s' (use .obj or "
                          ".ply)",
                          path, ext.c_str());
  struct stat sb;
  if (stat(path, &sb) != 0)
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot open: %s", path,
                          std::strerror(errno));
  if (!S_ISREG(sb.st_mode)) /* a FIFO would block the reader forever */
    return satf_error_set(err, SATF_ERR_IO, "%s: not a regular file", path);
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe)
      return satf_error_set(err, SATF_ERR_IO, "%s: cannot open for reading",
                            path);
  }
  quiet_openmesh();
  satf_mesh *m = nullptr;
  satf_status st = SATF_OK;
  try {
    m = new_mesh();
    OpenMesh::IO::Options opt = OpenMesh::IO::Options::VertexNormal |
                                OpenMesh::IO::Options::VertexTexCoord;
    if (!OpenMesh::IO::read_mesh(m->om, path, opt)) {
      st = satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: OpenMesh could not parse the file as %s", path,
                          ext.c_str() + 1);
    } else if (m->om.n_vertices() > kMaxVertices ||
               m->om.n_faces() > kMaxTriangles) {
      st = satf_error_set(err, SATF_ERR_FORMAT, "%s: mesh too large", path);
    } else {
      if (!opt.check(OpenMesh::IO::Options::VertexTexCoord))
        for (auto vh : m->om.vertices())
          m->om.set_texcoord2D(vh, TriMesh::TexCoord2D(0.0f, 0.0f));
      m->verts.assign(m->om.n_vertices(), satf_mesh_vertex{});
      pull_indices(m);
      if (opt.check(OpenMesh::IO::Options::VertexNormal)) {
        m->om.update_face_normals();
        pull_vertices(m);
      } else {
        recompute_normals(m);
      }
      st = check_read_mesh(path, ext, m, err);
    }
  } catch (const std::bad_alloc &) {
    st = satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  } catch (const std::exception &e) {
    st = satf_error_set(err, SATF_ERR_FORMAT, "%s: OpenMesh: %s", path,
                        e.what());
  }
  if (st) {
    delete m;
    return st;
  }
  *out = m;
  return SATF_OK;
}

} // extern "C"
