/* vdb_openvdb.cpp - see satf/vdb.h. The project's only OpenVDB translation
 * unit: every entry point catches all exceptions and turns them into a
 * satf_status, because none may unwind into C callers. */
#include "satf/density.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

extern "C" {
#include "satf/common.h"
}
#include "isolate.h"

struct satf_vdb_grid {
  openvdb::FloatGrid::ConstPtr grid;
};

struct satf_vdb_builder {
  openvdb::FloatGrid::Ptr grid;
  double voxel_size;
};

namespace {

/* Index coordinates beyond this are treated as outside any grid: it keeps
 * floor() and the +1 of trilinear lookups far from int32 overflow. */
constexpr double kMaxIndex = 1.0e9;
/* Gaussians are cut off at this many standard deviations along each axis. */
constexpr double kTruncation = 3.0;
/* Footprint limit per axis, so one call cannot run for minutes. */
constexpr int kMaxFootprint = 256;
/* Limit on the Gaussians one tube segment is split into. */
constexpr double kMaxTubeGaussians = 4194304.0;

void init_openvdb() {
  /* openvdb::initialize registers grid types; it must precede any file I/O
   * and is not meant to race with itself. */
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

satf_status fail_exception(satf_error *err, const char *what,
                           const std::exception &e) {
  if (dynamic_cast<const std::bad_alloc *>(&e))
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", what);
  return satf_error_set(err, SATF_ERR_INTERNAL, "%s: %s", what, e.what());
}

bool all_finite3(const float v[3]) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

satf_vdb_grid *wrap_grid(openvdb::FloatGrid::ConstPtr grid) {
  satf_vdb_grid *g = new (std::nothrow) satf_vdb_grid;
  if (g)
    g->grid = std::move(grid);
  return g;
}

/* Mass of a 1-D unit Gaussian centred at c with width sigma over [a, b]. */
double gaussian_interval_mass(double a, double b, double c, double sigma) {
  const double s = 1.0 / (std::sqrt(2.0) * sigma);
  return 0.5 * (std::erf((b - c) * s) - std::erf((a - c) * s));
}

/* First and last voxel along one axis touched by a Gaussian at c truncated
 * at kTruncation sigma. Voxel i spans [(i - 1/2) h, (i + 1/2) h]. */
void gaussian_footprint(double c, double sigma, double h, double *first,
                        double *last) {
  *first = std::floor((c - kTruncation * sigma) / h + 0.5);
  *last = std::floor((c + kTruncation * sigma) / h + 0.5);
}

/* Per-voxel weights along one axis: the truncated Gaussian's mass in each
 * voxel, renormalised to sum to 1 so that splatting conserves mass exactly
 * whatever the voxel size. */
int axis_weights(double c, double sigma, double h, std::vector<double> *w) {
  double first, last;
  gaussian_footprint(c, sigma, h, &first, &last);
  const double lo = c - kTruncation * sigma, hi = c + kTruncation * sigma;
  const int n = static_cast<int>(last - first) + 1;
  w->resize(static_cast<size_t>(n));
  double sum = 0.0;
  for (int k = 0; k < n; ++k) {
    const double i = first + k;
    const double a = std::max((i - 0.5) * h, lo);
    const double b = std::min((i + 0.5) * h, hi);
    (*w)[static_cast<size_t>(k)] =
        b > a ? gaussian_interval_mass(a, b, c, sigma) : 0.0;
    sum += (*w)[static_cast<size_t>(k)];
  }
  for (double &x : *w)
    x /= sum;
  return static_cast<int>(first);
}

/* Checks that a Gaussian at c of width sigma fits the limits above. */
satf_status check_gaussian(const satf_vdb_builder *b, const float c[3],
                           float sigma, const char *what, satf_error *err) {
  if (!all_finite3(c))
    return satf_error_set(err, SATF_ERR_ARGUMENT, "%s: non-finite position",
                          what);
  if (!(sigma > 0.0f) || !std::isfinite(sigma))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: sigma must be positive and finite, got %g", what,
                          static_cast<double>(sigma));
  const double h = b->voxel_size;
  for (int a = 0; a < 3; ++a) {
    double first, last;
    gaussian_footprint(c[a], sigma, h, &first, &last);
    if (!(std::fabs(first) < kMaxIndex && std::fabs(last) < kMaxIndex))
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "%s: position %g is too far from the origin for "
                            "voxel size %g",
                            what, static_cast<double>(c[a]), h);
    if (last - first + 1.0 > kMaxFootprint)
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "%s: sigma %g spans %.0f voxels of size %g; at "
                            "most %d are supported, use larger voxels",
                            what, static_cast<double>(sigma),
                            last - first + 1.0, h, kMaxFootprint);
  }
  return SATF_OK;
}

/* Adds the voxel integrals of an isotropic 3-D Gaussian (see
 * satf_vdb_builder_add_gaussian); the caller has run check_gaussian. Being
 * separable, the 3-D voxel integral is the product of three 1-D ones. */
void splat_gaussian(satf_vdb_builder *b, const double c[3], double sigma,
                    double mass) {
  std::vector<double> wx, wy, wz;
  const int x0 = axis_weights(c[0], sigma, b->voxel_size, &wx);
  const int y0 = axis_weights(c[1], sigma, b->voxel_size, &wy);
  const int z0 = axis_weights(c[2], sigma, b->voxel_size, &wz);
  const double density = mass / (b->voxel_size * b->voxel_size * b->voxel_size);
  openvdb::FloatGrid::Accessor acc = b->grid->getAccessor();
  for (size_t i = 0; i < wx.size(); ++i) {
    for (size_t j = 0; j < wy.size(); ++j) {
      const double wxy = density * wx[i] * wy[j];
      if (wxy == 0.0)
        continue;
      for (size_t k = 0; k < wz.size(); ++k) {
        const float v = static_cast<float>(wxy * wz[k]);
        if (v == 0.0f)
          continue;
        const openvdb::Coord ijk(x0 + static_cast<int>(i),
                                 y0 + static_cast<int>(j),
                                 z0 + static_cast<int>(k));
        acc.modifyValue(ijk, [v](float &x) { x += v; });
      }
    }
  }
}

/* Grid names in a file, quoted and comma separated, for error messages. */
std::string grid_names(const openvdb::io::File &file) {
  std::string names;
  for (openvdb::io::File::NameIterator it = file.beginName();
       it != file.endName(); ++it) {
    if (!names.empty())
      names += ", ";
    names += "'" + it.gridName() + "'";
  }
  return names.empty() ? std::string("none") : names;
}

/* Sequential reader over a file with a known size; every read is checked
 * against the bytes left, so lengths in a damaged file cannot mislead it. */
struct ByteReader {
  FILE *f;
  int64_t size, pos;
  bool ok;

  bool read(void *dst, int64_t n) {
    if (!ok || n < 0 || n > size - pos ||
        std::fread(dst, 1, static_cast<size_t>(n), f) != static_cast<size_t>(n))
      return ok = false;
    pos += n;
    return true;
  }
  bool seek(int64_t to) {
    if (!ok || to < 0 || to > size || fseeko(f, to, SEEK_SET) != 0)
      return ok = false;
    pos = to;
    return true;
  }
  bool skip(int64_t n) {
    if (n < 0 || n > size - pos)
      return ok = false;
    return seek(pos + n);
  }
  uint32_t u32() {
    uint32_t v = 0;
    read(&v, sizeof v);
    return v;
  }
  int64_t i64() {
    int64_t v = 0;
    read(&v, sizeof v);
    return v;
  }
  /* OpenVDB strings are a uint32 length followed by the bytes. */
  void skip_string() { skip(u32()); }
};

/* Skips a MetaMap (OpenVDB's MetaMap::readMeta): a count, then a name, a
 * type name and a size-prefixed value per entry. Every length is checked
 * against the file, so a damaged one cannot make OpenVDB allocate and fill
 * gigabytes for a string. */
void skip_meta_map(ByteReader &r) {
  const uint32_t count = r.u32();
  for (uint32_t i = 0; i < count && r.ok; ++i) {
    r.skip_string(); /* name */
    r.skip_string(); /* type */
    r.skip(r.u32()); /* value */
  }
}

/* Walks the VDB header and grid descriptors (the layout of OpenVDB's
 * Archive::readHeader, MetaMap::readMeta and GridDescriptor::read) and checks
 * that every grid's recorded extent lies inside the file. OpenVDB itself does
 * not check stream state while reading voxel buffers, so a file cut inside
 * the data would otherwise load as a silently damaged grid. Files without
 * grid offsets (old or streamed) are left to OpenVDB. */
satf_status check_vdb_layout(ByteReader &r, uint32_t version, const char *path,
                             satf_error *err) {
  if (version >= 211)
    r.skip(8); /* library major and minor version */
  if (version >= 212) {
    char has_offsets = 0;
    r.read(&has_offsets, 1);
    if (r.ok && !has_offsets)
      return SATF_OK;
  }
  if (version >= 220 && version < 222)
    r.skip(1);                      /* file-wide compression flag */
  r.skip(version >= 218 ? 36 : 16); /* UUID, as text from 218 on */
  skip_meta_map(r);
  const uint32_t grid_count = r.u32();
  for (uint32_t i = 0; i < grid_count && r.ok; ++i) {
    r.skip_string(); /* unique name */
    r.skip_string(); /* type */
    if (version >= 216)
      r.skip_string(); /* instance parent */
    const int64_t grid_pos = r.i64(), block_pos = r.i64(), end_pos = r.i64();
    if (!r.ok)
      break;
    if (!(r.pos <= grid_pos && grid_pos <= block_pos && block_pos <= end_pos &&
          end_pos <= r.size))
      return satf_error_set(
          err, SATF_ERR_CORRUPT,
          "%s: grid %u of %u claims bytes %lld to %lld but "
          "the file has %lld (truncated or damaged)",
          path, i + 1, grid_count, static_cast<long long>(grid_pos),
          static_cast<long long>(end_pos), static_cast<long long>(r.size));
    /* The grid's own metadata must end before its voxel data. */
    r.seek(grid_pos);
    if (version >= 222)
      r.skip(4); /* per-grid compression flags */
    skip_meta_map(r);
    if (r.ok && r.pos > block_pos)
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: the metadata of grid %u runs into its voxel "
                            "data (damaged file)",
                            path, i + 1);
    r.seek(end_pos);
  }
  if (!r.ok)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: VDB header is truncated or damaged near byte "
                          "%lld of %lld",
                          path, static_cast<long long>(r.pos),
                          static_cast<long long>(r.size));
  return SATF_OK;
}

/* Rejects files that are not VDB files, come from a newer OpenVDB or are
 * truncated before OpenVDB itself parses them, so those cases get precise
 * statuses and never reach OpenVDB's unchecked buffer reads. */
satf_status check_vdb_file(const char *path, int64_t *size, satf_error *err) {
  /* O_NONBLOCK: opening a FIFO for reading would wait for a writer
   * forever; it is refused below with every other non-regular file. */
  const int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0)
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot open: %s", path,
                          std::strerror(errno));
  struct stat st_buf;
  if (fstat(fd, &st_buf) != 0 || !S_ISREG(st_buf.st_mode)) {
    close(fd);
    return satf_error_set(err, SATF_ERR_IO, "%s: not a regular file", path);
  }
  FILE *f = fdopen(fd, "rb");
  if (!f) {
    const int e = errno;
    close(fd);
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot open: %s", path,
                          std::strerror(e));
  }
  ByteReader r{f, 0, 0, true};
  if (fseeko(f, 0, SEEK_END) != 0 || (r.size = ftello(f)) < 0 ||
      fseeko(f, 0, SEEK_SET) != 0) {
    const int e = errno;
    std::fclose(f);
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot seek: %s", path,
                          std::strerror(e));
  }
  const int64_t magic = r.i64();
  satf_status st = SATF_OK;
  if (!r.ok || magic != openvdb::OPENVDB_MAGIC) {
    st = satf_error_set(err, SATF_ERR_FORMAT,
                        "%s: not a VDB file (no VDB magic number)", path);
  } else {
    const uint32_t version = r.u32();
    if (!r.ok)
      st = satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: VDB file is truncated after its magic number",
                          path);
    else if (version > openvdb::OPENVDB_FILE_VERSION)
      st = satf_error_set(err, SATF_ERR_VERSION,
                          "%s: VDB file format %u is newer than the %u this "
                          "build of OpenVDB reads",
                          path, version, openvdb::OPENVDB_FILE_VERSION);
    else
      st = check_vdb_layout(r, version, path, err);
  }
  std::fclose(f);
  *size = r.size;
  return st;
}

satf_status read_grid(const char *path, const char *grid_name,
                      openvdb::FloatGrid::Ptr *out, satf_error *err) {
  openvdb::io::File file(path);
  /* Delayed loading would read voxel data lazily from a memory map during
   * sampling, where a truncated file faults instead of failing here. */
  file.open(false);
  if (!file.hasGrid(grid_name))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: no grid named '%s'; grids in the file: %s", path,
                          grid_name, grid_names(file).c_str());
  openvdb::GridBase::Ptr meta = file.readGridMetadata(grid_name);
  if (!meta->isType<openvdb::FloatGrid>())
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: grid '%s' holds %s values, not a float density",
                          path, grid_name, meta->valueType().c_str());
  openvdb::FloatGrid::Ptr grid =
      openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid(grid_name));
  file.close();
  if (!grid)
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: grid '%s' is not a FloatGrid", path, grid_name);
  if (!grid->transform().isLinear())
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: grid '%s' has a non-linear (frustum) transform",
                          path, grid_name);
  *out = grid;
  return SATF_OK;
}

/* ---- Reading in a child process (isolate.h) ----------------------------
 * OpenVDB 10 trusts the sizes inside compressed voxel data: about one
 * single-byte change in a few hundred there overflows a heap buffer, which
 * crashes the reader or silently corrupts the heap. Checking that data
 * before OpenVDB would mean re-implementing its whole topology and
 * compression parser, so the file is parsed in a child process instead, and
 * the child sends the grid back as fixed-layout records that the parent
 * checks field by field and builds its own tree from. */

enum RecordTag { kTagHeader = 1, kTagTile = 2, kTagLeaf = 3 };
using FloatLeaf = openvdb::FloatTree::LeafNodeType;
using FloatUpper = openvdb::FloatTree::RootNodeType::ChildNodeType;
using FloatLower = FloatUpper::ChildNodeType;

struct HeaderRecord {
  double matrix[16]; /* the index-to-world affine map, row-major */
  float background;
};
struct TileRecord {
  int32_t level, xyz[3]; /* level 1 = a tile of leaf size */
  float value;
  uint32_t active;
};
struct LeafRecord {
  int32_t origin[3];
  uint32_t pad;
  uint64_t mask[FloatLeaf::NodeMaskType::WORD_COUNT];
  float values[FloatLeaf::SIZE];
};
static_assert(sizeof(LeafRecord) <= SATF_ISOLATED_MAX_RECORD,
              "a leaf must fit one record");
static_assert(sizeof(FloatLeaf::NodeMaskType::Word) == sizeof(uint64_t),
              "leaf masks are 64-bit words");

/* Index coordinates of rebuilt nodes stay within this, far from overflow. */
constexpr int32_t kMaxCoord = 1 << 30;

struct ReadJob {
  const char *path, *grid_name;
};

/* Sends every tile and every leaf of the grid: a full traversal, so a
 * damaged node crashes the child rather than a later sampler. Serial code
 * only (see isolate.c for why). */
bool send_tree(const openvdb::FloatGrid &grid, int fd) {
  HeaderRecord h{};
  const openvdb::Mat4d m =
      grid.transform().baseMap()->getAffineMap()->getMat4();
  std::memcpy(h.matrix, m.asPointer(), sizeof h.matrix);
  h.background = grid.background();
  bool ok = satf_isolated_send(fd, kTagHeader, &h, sizeof h) == 0;
  openvdb::FloatTree::ValueAllCIter tile = grid.tree().cbeginValueAll();
  tile.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);
  for (; ok && tile; ++tile) {
    /* Every internal node holds thousands of inactive background tiles;
     * the rebuilt tree gets those by itself. */
    if (!tile.isValueOn() && *tile == h.background)
      continue;
    const openvdb::Coord c = tile.getCoord();
    const TileRecord t{static_cast<int32_t>(tile.getLevel()),
                       {c.x(), c.y(), c.z()},
                       *tile,
                       tile.isValueOn() ? 1u : 0u};
    ok = satf_isolated_send(fd, kTagTile, &t, sizeof t) == 0;
  }
  LeafRecord r{};
  for (openvdb::FloatTree::LeafCIter leaf = grid.tree().cbeginLeaf();
       ok && leaf; ++leaf) {
    const openvdb::Coord c = leaf->origin();
    r.origin[0] = c.x(), r.origin[1] = c.y(), r.origin[2] = c.z();
    for (openvdb::Index w = 0; w < FloatLeaf::NodeMaskType::WORD_COUNT; ++w)
      r.mask[w] = leaf->getValueMask().getWord<uint64_t>(w);
    for (openvdb::Index i = 0; i < FloatLeaf::SIZE; ++i)
      r.values[i] = leaf->getValue(i);
    ok = satf_isolated_send(fd, kTagLeaf, &r, sizeof r) == 0;
  }
  return ok;
}

/* The child's part of satf_vdb_read. */
satf_status send_grid(void *ctx, int fd, satf_error *err) {
  const ReadJob *job = static_cast<const ReadJob *>(ctx);
  try {
    openvdb::FloatGrid::Ptr grid;
    satf_status st = read_grid(job->path, job->grid_name, &grid, err);
    if (st != SATF_OK)
      return st;
    if (!send_tree(*grid, fd))
      return satf_error_set(err, SATF_ERR_IO,
                            "%s: cannot hand grid '%s' to the parent process",
                            job->path, job->grid_name);
    return SATF_OK;
  } catch (const std::bad_alloc &) {
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "%s: out of memory reading grid '%s' (the file may "
                          "be damaged)",
                          job->path, job->grid_name);
  } catch (const std::exception &e) {
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: damaged VDB file: %s",
                          job->path, e.what());
  } catch (...) {
    return satf_error_set(err, SATF_ERR_INTERNAL,
                          "%s: unknown error reading grid '%s'", job->path,
                          job->grid_name);
  }
}

/* The parent's copy, built from the child's records. */
struct GridReceiver {
  const char *path, *grid_name;
  openvdb::FloatGrid::Ptr grid;
};

bool coord_ok(const int32_t xyz[3], int32_t align) {
  for (int a = 0; a < 3; ++a)
    if (xyz[a] < -kMaxCoord || xyz[a] > kMaxCoord || xyz[a] % align != 0)
      return false;
  return true;
}

satf_status receive_header(GridReceiver *r, const HeaderRecord &h,
                           satf_error *err) {
  for (double x : h.matrix)
    if (!std::isfinite(x))
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: grid '%s' has a non-finite transform", r->path,
                            r->grid_name);
  if (!std::isfinite(h.background))
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: grid '%s' has a non-finite background value",
                          r->path, r->grid_name);
  openvdb::Mat4d m;
  std::memcpy(m.asPointer(), h.matrix, sizeof h.matrix);
  /* Throws for a singular or non-affine matrix. */
  openvdb::math::Transform::Ptr xform =
      openvdb::math::Transform::createLinearTransform(m);
  const double volume = xform->voxelVolume();
  if (!(volume > 0.0) || !std::isfinite(volume))
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: grid '%s' has voxels of volume %g", r->path,
                          r->grid_name, volume);
  r->grid = openvdb::FloatGrid::create(h.background);
  r->grid->setTransform(xform);
  r->grid->setName(r->grid_name);
  r->grid->setGridClass(openvdb::GRID_FOG_VOLUME);
  return SATF_OK;
}

satf_status receive_tile(GridReceiver *r, const TileRecord &t,
                         satf_error *err) {
  /* A tile at level L spans one child of a level-L node. */
  static const int32_t span[4] = {1, FloatLeaf::DIM, FloatLower::DIM,
                                  FloatUpper::DIM};
  if (t.level < 1 || t.level > 3 || !coord_ok(t.xyz, span[t.level]) ||
      !std::isfinite(t.value) || t.active > 1)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: grid '%s' has a damaged tile (level %d at "
                          "%d %d %d, value %g)",
                          r->path, r->grid_name, t.level, t.xyz[0], t.xyz[1],
                          t.xyz[2], static_cast<double>(t.value));
  r->grid->tree().addTile(static_cast<openvdb::Index>(t.level),
                          openvdb::Coord(t.xyz[0], t.xyz[1], t.xyz[2]), t.value,
                          t.active != 0);
  return SATF_OK;
}

satf_status receive_leaf(GridReceiver *r, const LeafRecord &l,
                         satf_error *err) {
  if (!coord_ok(l.origin, FloatLeaf::DIM))
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: grid '%s' has a leaf at %d %d %d", r->path,
                          r->grid_name, l.origin[0], l.origin[1], l.origin[2]);
  for (openvdb::Index i = 0; i < FloatLeaf::SIZE; ++i) {
    if (std::isfinite(l.values[i]))
      continue;
    const openvdb::Coord c =
        FloatLeaf::offsetToLocalCoord(i) +
        openvdb::Coord(l.origin[0], l.origin[1], l.origin[2]);
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: grid '%s' holds a non-finite density at voxel "
                          "%d %d %d (damaged file)",
                          r->path, r->grid_name, c.x(), c.y(), c.z());
  }
  FloatLeaf *leaf = r->grid->tree().touchLeaf(
      openvdb::Coord(l.origin[0], l.origin[1], l.origin[2]));
  FloatLeaf::NodeMaskType mask;
  for (openvdb::Index w = 0; w < FloatLeaf::NodeMaskType::WORD_COUNT; ++w)
    mask.getWord<uint64_t>(w) = l.mask[w];
  std::memcpy(leaf->buffer().data(), l.values, sizeof l.values);
  leaf->setValueMask(mask);
  return SATF_OK;
}

/* satf_isolated_recv_fn: one record from the child; a header comes first
 * and once. */
satf_status receive_record(void *ctx, int tag, const void *data, size_t size,
                           satf_error *err) {
  GridReceiver *r = static_cast<GridReceiver *>(ctx);
  try {
    if (tag == kTagHeader && !r->grid && size == sizeof(HeaderRecord)) {
      HeaderRecord h;
      std::memcpy(&h, data, sizeof h);
      return receive_header(r, h, err);
    }
    if (tag == kTagTile && r->grid && size == sizeof(TileRecord)) {
      TileRecord t;
      std::memcpy(&t, data, sizeof t);
      return receive_tile(r, t, err);
    }
    if (tag == kTagLeaf && r->grid && size == sizeof(LeafRecord)) {
      static thread_local LeafRecord l;
      std::memcpy(&l, data, sizeof l);
      return receive_leaf(r, l, err);
    }
    return satf_error_set(err, SATF_ERR_INTERNAL,
                          "%s: unexpected record %d of %zu bytes from the VDB "
                          "reader",
                          r->path, tag, size);
  } catch (const std::exception &e) {
    if (dynamic_cast<const openvdb::ArithmeticError *>(&e))
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: grid '%s' has an invalid transform: %s",
                            r->path, r->grid_name, e.what());
    return fail_exception(err, r->path, e);
  } catch (...) {
    return satf_error_set(err, SATF_ERR_INTERNAL, "%s: unknown exception",
                          r->path);
  }
}

/* Time the child may take: generous for slow disks, yet a hang on a damaged
 * file ends. */
unsigned read_seconds(int64_t size) {
  const int64_t s = 10 + size / (4 << 20);
  return static_cast<unsigned>(std::min<int64_t>(s, 3600));
}

template <typename Accessor>
float sample_at(const openvdb::FloatGrid &grid, Accessor &acc,
                const float p[3]) {
  const openvdb::Vec3d ip =
      grid.transform().worldToIndex(openvdb::Vec3d(p[0], p[1], p[2]));
  /* Also false for NaN, which must not reach the integer conversions. */
  if (!(std::fabs(ip.x()) < kMaxIndex && std::fabs(ip.y()) < kMaxIndex &&
        std::fabs(ip.z()) < kMaxIndex))
    return grid.background();
  return openvdb::tools::BoxSampler::sample(acc, ip);
}

/* A seekable output buffer over a file descriptor that keeps the first
 * write or seek error: OpenVDB's io::File::write never checks its stream,
 * so a full disk used to leave a truncated file that was renamed into place
 * as if complete. Seekable because OpenVDB writes each grid's offsets back
 * into its descriptor. */
class FdWriteBuf : public std::streambuf {
public:
  explicit FdWriteBuf(int fd) : fd_(fd) { setp(buf_, buf_ + sizeof buf_); }
  int error() const { return error_; }

protected:
  int_type overflow(int_type c) override {
    if (drain() != 0)
      return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain(); }
  pos_type seekoff(off_type off, std::ios_base::seekdir dir,
                   std::ios_base::openmode) override {
    if (drain() != 0)
      return pos_type(off_type(-1));
    const int whence = dir == std::ios_base::beg   ? SEEK_SET
                       : dir == std::ios_base::cur ? SEEK_CUR
                                                   : SEEK_END;
    const off_t at = lseek(fd_, static_cast<off_t>(off), whence);
    if (at < 0) {
      error_ = errno;
      return pos_type(off_type(-1));
    }
    return pos_type(static_cast<off_type>(at));
  }
  pos_type seekpos(pos_type pos, std::ios_base::openmode which) override {
    return seekoff(off_type(pos), std::ios_base::beg, which);
  }

private:
  int drain() {
    for (char *p = pbase(); !error_ && p < pptr();) {
      const ssize_t n = ::write(fd_, p, static_cast<size_t>(pptr() - p));
      if (n < 0 && errno == EINTR)
        continue;
      if (n <= 0)
        error_ = n < 0 ? errno : EIO;
      else
        p += n;
    }
    setp(buf_, buf_ + sizeof buf_);
    return error_ ? -1 : 0;
  }

  int fd_, error_ = 0;
  char buf_[1 << 16];
};

/* Archive::write(std::ostream&, ...) is protected; io::File::write wraps it
 * in an unchecked std::ofstream. */
class CheckedArchive : public openvdb::io::Archive {
public:
  void write_to(std::ostream &os, const openvdb::GridCPtrVec &grids,
                const openvdb::MetaMap &meta) const {
    write(os, grids, /*seekable=*/true, meta);
  }
};

/* OpenVDB's header holds a random UUID (36 characters after the magic
 * number, format version, library version and offsets flag), so the same
 * grids gave different bytes, and a different content-hashed name, on each
 * run. It is replaced by one derived from the rest of the file (a 128-bit
 * FNV-1a digest in UUID form): equal files get equal bytes, different
 * files still get different identifiers. Returns 0 or an errno; a header of
 * another layout is left alone. */
int fix_uuid(int fd) {
  constexpr off_t kAt = 21;
  constexpr size_t kLen = 36;
  char uuid[kLen];
  if (pread(fd, uuid, kLen, kAt) != static_cast<ssize_t>(kLen))
    return errno ? errno : EIO;
  for (size_t i = 0; i < kLen; ++i) {
    const bool dash = i == 8 || i == 13 || i == 18 || i == 23;
    if (dash ? uuid[i] != '-'
             : !std::isxdigit(static_cast<unsigned char>(uuid[i])))
      return 0;
  }
  uint64_t h[2] = {0xcbf29ce484222325ull, 0x84222325cbf29ce4ull};
  std::vector<unsigned char> buf(1 << 16);
  for (off_t at = kAt + static_cast<off_t>(kLen);;) {
    const ssize_t n = pread(fd, buf.data(), buf.size(), at);
    if (n < 0 && errno == EINTR)
      continue;
    if (n < 0)
      return errno;
    if (n == 0)
      break;
    for (ssize_t i = 0; i < n; ++i) {
      h[0] = (h[0] ^ buf[static_cast<size_t>(i)]) * 0x100000001b3ull;
      h[1] = (h[1] ^ buf[static_cast<size_t>(i)]) * 0x100000001b3ull + h[0];
    }
    at += n;
  }
  char hex[33];
  std::snprintf(hex, sizeof hex, "%016llx%016llx",
                static_cast<unsigned long long>(h[0]),
                static_cast<unsigned long long>(h[1]));
  char out[kLen + 1];
  std::snprintf(out, sizeof out, "%.8s-%.4s-%.4s-%.4s-%.12s", hex, hex + 8,
                hex + 12, hex + 16, hex + 20);
  if (pwrite(fd, out, kLen, kAt) != static_cast<ssize_t>(kLen))
    return errno ? errno : EIO;
  return 0;
}

/* Writes the grids to fd and checks every step: each write, the final
 * flush, fsync (where a full disk may first show) and close. Returns 0 or
 * the errno of the first failure; fd is closed either way. */
int write_vdb_fd(int fd, const openvdb::GridCPtrVec &grids,
                 const openvdb::MetaMap &meta) {
  int e = 0;
  {
    FdWriteBuf buf(fd);
    std::ostream os(&buf);
    CheckedArchive().write_to(os, grids, meta);
    os.flush();
    e = buf.error() ? buf.error() : os ? 0 : EIO;
  }
  if (!e)
    e = fix_uuid(fd);
  if (!e && fsync(fd) != 0 && errno != EINVAL && errno != EROFS)
    e = errno; /* EINVAL, EROFS: the target cannot be synced, e.g. a pipe */
  if (close(fd) != 0 && !e)
    e = errno;
  return e;
}

/* Writes grids to path through a temporary file renamed into place only
 * when every byte reached the disk; on failure nothing is left behind. */
satf_status write_grids(const openvdb::GridCPtrVec &grids,
                        const openvdb::MetaMap &meta, const char *path,
                        satf_error *err) {
  char tmp[4096];
  satf_status st = satf_temp_path(path, tmp, sizeof tmp, err);
  if (st != SATF_OK)
    return st;
  /* read back too: fix_uuid hashes what was written */
  const int fd = open(tmp, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0)
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot create %s: %s", path,
                          tmp, std::strerror(errno));
  int e = 0;
  try {
    e = write_vdb_fd(fd, grids, meta);
  } catch (const std::exception &ex) {
    close(fd); /* write_vdb_fd closes it only when it returns */
    unlink(tmp);
    return fail_exception(err, path, ex);
  }
  if (e != 0) {
    unlink(tmp);
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot write: %s", path,
                          std::strerror(e));
  }
  return satf_commit_temp(tmp, path, err);
}

satf_status write_grid(openvdb::GridBase::Ptr grid, const char *path,
                       satf_error *err) {
  try {
    openvdb::GridCPtrVec grids;
    grids.push_back(grid);
    openvdb::MetaMap meta;
    meta.insertMeta("creator",
                    openvdb::StringMetadata("satf " SATF_VERSION_STRING));
    return write_grids(grids, meta, path, err);
  } catch (const std::exception &e) {
    return fail_exception(err, path, e);
  } catch (...) {
    return satf_error_set(err, SATF_ERR_INTERNAL, "%s: unknown exception",
                          path);
  }
}

} // namespace

extern "C" {

satf_status satf_vdb_read(const char *path, const char *grid_name,
                          satf_vdb_grid **out, satf_error *err) {
  if (out)
    *out = nullptr;
  if (!path || !grid_name || !out)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "satf_vdb_read: NULL path, grid name or output");
  int64_t size = 0;
  satf_status st = check_vdb_file(path, &size, err);
  if (st != SATF_OK)
    return st;
  try {
    /* Before the fork: the child must not run a one-time initialisation
     * whose lock another thread might hold (isolate.c). */
    init_openvdb();
  } catch (const std::exception &e) {
    return fail_exception(err, path, e);
  }
  ReadJob job{path, grid_name};
  GridReceiver rx{path, grid_name, nullptr};
  st = satf_isolated_run(send_grid, &job, receive_record, &rx, path, "VDB file",
                         read_seconds(size), err);
  if (st != SATF_OK)
    return st;
  if (!rx.grid)
    return satf_error_set(err, SATF_ERR_INTERNAL,
                          "%s: the VDB reader sent no grid", path);
  *out = wrap_grid(rx.grid);
  if (!*out)
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  return SATF_OK;
}

void satf_vdb_grid_destroy(satf_vdb_grid *g) { delete g; }

satf_vdb_grid *satf_vdb_grid_share(const satf_vdb_grid *g) {
  return g ? wrap_grid(g->grid) : nullptr;
}

float satf_vdb_sample(const satf_vdb_grid *g, const float world_xyz[3]) {
  openvdb::FloatGrid::ConstUnsafeAccessor acc =
      g->grid->getConstUnsafeAccessor();
  return sample_at(*g->grid, acc, world_xyz);
}

void satf_vdb_sample_many(const satf_vdb_grid *g, size_t n, const float *xyz,
                          float *out) {
  /* An unregistered accessor: the tree never changes after creation, and a
   * per-call cache is what makes concurrent calls safe. */
  openvdb::FloatGrid::ConstUnsafeAccessor acc =
      g->grid->getConstUnsafeAccessor();
  for (size_t i = 0; i < n; ++i)
    out[i] = sample_at(*g->grid, acc, xyz + 3 * i);
}

int satf_vdb_bbox(const satf_vdb_grid *g, float lo[3], float hi[3]) {
  const openvdb::CoordBBox box = g->grid->evalActiveVoxelBoundingBox();
  if (box.empty()) {
    for (int a = 0; a < 3; ++a)
      lo[a] = hi[a] = 0.0f;
    return 0;
  }
  const openvdb::Vec3d imin = box.min().asVec3d() - openvdb::Vec3d(0.5);
  const openvdb::Vec3d imax = box.max().asVec3d() + openvdb::Vec3d(0.5);
  openvdb::Vec3d wlo(INFINITY), whi(-INFINITY);
  for (int corner = 0; corner < 8; ++corner) {
    const openvdb::Vec3d ic(corner & 1 ? imax.x() : imin.x(),
                            corner & 2 ? imax.y() : imin.y(),
                            corner & 4 ? imax.z() : imin.z());
    const openvdb::Vec3d wc = g->grid->transform().indexToWorld(ic);
    wlo = openvdb::math::minComponent(wlo, wc);
    whi = openvdb::math::maxComponent(whi, wc);
  }
  for (int a = 0; a < 3; ++a) {
    lo[a] = static_cast<float>(wlo[a]);
    hi[a] = static_cast<float>(whi[a]);
  }
  return 1;
}

float satf_vdb_voxel_size(const satf_vdb_grid *g) {
  return static_cast<float>(std::cbrt(g->grid->transform().voxelVolume()));
}

double satf_vdb_total_mass(const satf_vdb_grid *g) {
  double sum = 0.0;
  for (openvdb::FloatGrid::ValueOnCIter it = g->grid->cbeginValueOn(); it; ++it)
    sum += static_cast<double>(*it) * static_cast<double>(it.getVoxelCount());
  return sum * g->grid->transform().voxelVolume();
}

satf_status satf_vdb_builder_create(float voxel_size, satf_vdb_builder **out,
                                    satf_error *err) {
  if (!out)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "satf_vdb_builder_create: NULL output");
  *out = nullptr;
  if (!(voxel_size > 1e-6f) || !std::isfinite(voxel_size))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "vdb builder: voxel size must be finite and above "
                          "1e-6, got %g",
                          static_cast<double>(voxel_size));
  try {
    init_openvdb();
    satf_vdb_builder *b = new satf_vdb_builder;
    b->voxel_size = voxel_size;
    b->grid = openvdb::FloatGrid::create(0.0f);
    b->grid->setTransform(
        openvdb::math::Transform::createLinearTransform(b->voxel_size));
    b->grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    *out = b;
    return SATF_OK;
  } catch (const std::exception &e) {
    return fail_exception(err, "vdb builder", e);
  } catch (...) {
    return satf_error_set(err, SATF_ERR_INTERNAL, "%s: unknown exception",
                          "vdb builder");
  }
}

void satf_vdb_builder_destroy(satf_vdb_builder *b) { delete b; }

satf_status satf_vdb_builder_add_gaussian(satf_vdb_builder *b,
                                          const float center[3], float sigma,
                                          float mass, satf_error *err) {
  const char *what = "vdb builder gaussian";
  if (!b || !center)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "%s: NULL argument", what);
  satf_status st = check_gaussian(b, center, sigma, what, err);
  if (st != SATF_OK)
    return st;
  if (!(mass >= 0.0f) || !std::isfinite(mass))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: mass must be finite and >= 0, got %g", what,
                          static_cast<double>(mass));
  try {
    const double c[3] = {center[0], center[1], center[2]};
    splat_gaussian(b, c, sigma, mass);
    return SATF_OK;
  } catch (const std::exception &e) {
    return fail_exception(err, what, e);
  } catch (...) {
    return satf_error_set(err, SATF_ERR_INTERNAL, "%s: unknown exception",
                          what);
  }
}

satf_status satf_vdb_builder_add_tube(satf_vdb_builder *b, const float p0[3],
                                      const float p1[3], float sigma,
                                      float mass_per_length, satf_error *err) {
  const char *what = "vdb builder tube";
  if (!b || !p0 || !p1)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "%s: NULL argument", what);
  /* Every Gaussian lies between the end points, so checking both bounds
   * them all. */
  satf_status st = check_gaussian(b, p0, sigma, what, err);
  if (st == SATF_OK)
    st = check_gaussian(b, p1, sigma, what, err);
  if (st != SATF_OK)
    return st;
  if (!(mass_per_length >= 0.0f) || !std::isfinite(mass_per_length))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: mass per length must be finite and >= 0, got %g",
                          what, static_cast<double>(mass_per_length));
  const double d[3] = {static_cast<double>(p1[0]) - p0[0],
                       static_cast<double>(p1[1]) - p0[1],
                       static_cast<double>(p1[2]) - p0[2]};
  const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (length == 0.0 || mass_per_length == 0.0f)
    return SATF_OK;
  /* The segment convolved with a Gaussian, by midpoint quadrature: Gaussians
   * at most sigma apart sum to a smooth tube (the ripple is ~1e-8 relative),
   * and at most an eighth of a voxel apart when sigma is below the voxel
   * size, so each voxel's share of the strand's length is resolved. */
  const double spacing =
      std::max(static_cast<double>(sigma), b->voxel_size / 8.0);
  const double count = std::ceil(length / spacing);
  if (count > kMaxTubeGaussians)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: segment of length %g is %.0f splats long; at "
                          "most %.0f are supported",
                          what, length, count, kMaxTubeGaussians);
  const long n = static_cast<long>(count);
  const double mass = mass_per_length * length / static_cast<double>(n);
  try {
    for (long k = 0; k < n; ++k) {
      const double t = (static_cast<double>(k) + 0.5) / static_cast<double>(n);
      const double c[3] = {p0[0] + t * d[0], p0[1] + t * d[1],
                           p0[2] + t * d[2]};
      splat_gaussian(b, c, sigma, mass);
    }
    return SATF_OK;
  } catch (const std::exception &e) {
    return fail_exception(err, what, e);
  } catch (...) {
    return satf_error_set(err, SATF_ERR_INTERNAL, "%s: unknown exception",
                          what);
  }
}

satf_status satf_vdb_builder_write(const satf_vdb_builder *b, const char *path,
                                   const char *grid_name, satf_error *err) {
  if (!b || !path || !grid_name || !grid_name[0])
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: vdb write needs a builder and a grid name",
                          path ? path : "(null)");
  try {
    /* A shallow copy shares the tree, so naming it leaves b untouched. */
    openvdb::FloatGrid::Ptr grid = b->grid->copy();
    grid->setName(grid_name);
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    return write_grid(grid, path, err);
  } catch (const std::exception &e) {
    return fail_exception(err, path, e);
  } catch (...) {
    return satf_error_set(err, SATF_ERR_INTERNAL, "%s: unknown exception",
                          path);
  }
}

satf_status satf_vdb_builder_to_grid(const satf_vdb_builder *b,
                                     satf_vdb_grid **out, satf_error *err) {
  if (out)
    *out = nullptr;
  if (!b || !out)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "satf_vdb_builder_to_grid: NULL argument");
  try {
    *out = wrap_grid(b->grid->deepCopy());
    if (!*out)
      return satf_error_set(err, SATF_ERR_NOMEM, "vdb builder: out of memory");
    return SATF_OK;
  } catch (const std::exception &e) {
    return fail_exception(err, "vdb builder", e);
  } catch (...) {
    return satf_error_set(err, SATF_ERR_INTERNAL, "%s: unknown exception",
                          "vdb builder");
  }
}

satf_status satf_vdb_write_mixed_test_file(const char *path, satf_error *err) {
  if (!path)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "satf_vdb_write_mixed_test_file: NULL path");
  try {
    init_openvdb();
    const openvdb::Coord origin(0, 0, 0);
    openvdb::FloatGrid::Ptr density = openvdb::FloatGrid::create(0.0f);
    density->setName("density");
    density->tree().setValue(origin, 1.0f);
    openvdb::Int32Grid::Ptr ids = openvdb::Int32Grid::create(0);
    ids->setName("ids");
    ids->tree().setValue(origin, 7);
    openvdb::Vec3SGrid::Ptr velocity =
        openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    velocity->setName("velocity");
    velocity->tree().setValue(origin, openvdb::Vec3s(1.0f, 2.0f, 3.0f));
    openvdb::GridCPtrVec grids{density, ids, velocity};
    return write_grids(grids, openvdb::MetaMap(), path, err);
  } catch (const std::exception &e) {
    return fail_exception(err, path, e);
  } catch (...) {
    return satf_error_set(err, SATF_ERR_INTERNAL, "%s: unknown exception",
                          path);
  }
}

} /* extern "C" */
