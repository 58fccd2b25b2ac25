/* density.h - the density level of the hierarchy (online/density/):
 * OpenVDB grids through the C++ shim, procedural strands in a cluster's
 * cross-section, and the sector features (SATF sec. 5.2) of every boundary
 * sector of a cluster's shells. */
#ifndef SATF_DENSITY_H
#define SATF_DENSITY_H

#include <stddef.h>

#include "satf/geometry.h"
#include "satf/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- OpenVDB grids ----
 * world-space hair density fields stored as OpenVDB FloatGrids.
 *
 * Owns two opaque handles: satf_vdb_grid, a read-only density grid that any
 * number of threads may sample at once, and satf_vdb_builder, which splats
 * strand hair into a density grid (SATF sec. 3.3 models each strand's
 * cross-section density as a Gaussian) and writes it as a fog-volume .vdb
 * that Blender and Houdini open. Plain C; the OpenVDB code lives in a single
 * C++ translation unit (online/vdb_openvdb.cpp) and no exception crosses
 * this interface. */

typedef struct satf_vdb_grid satf_vdb_grid;
typedef struct satf_vdb_builder satf_vdb_builder;

/* ---- Reading and sampling ---------------------------------------------- */

/* Opens the .vdb at path and loads its FloatGrid named grid_name into *out.
 * Errors name the file: SATF_ERR_IO (cannot open, or not a regular file),
 * SATF_ERR_FORMAT (not a VDB file, the grid is not a FloatGrid, or its
 * transform is not linear), SATF_ERR_VERSION (newer file format),
 * SATF_ERR_CORRUPT (damaged or truncated), SATF_ERR_ARGUMENT (no such grid;
 * the message lists the grids the file holds). The file is read completely
 * here, never lazily, and a file cut short anywhere is rejected. OpenVDB
 * parses the file in a child process that hands the grid back to be checked
 * and rebuilt, so damaged voxel data that crashes or hangs OpenVDB is
 * SATF_ERR_CORRUPT ("PATH: damaged VDB file: the reader crashed (SIGSEGV)")
 * instead of a crash of the caller. */
satf_status satf_vdb_read(const char *path, const char *grid_name,
                          satf_vdb_grid **out, satf_error *err);

/* Frees a grid (NULL is allowed). */
void satf_vdb_grid_destroy(satf_vdb_grid *g);

/* A second handle on g's voxels, which are shared, not copied (a grid never
 * changes once read): each handle is freed by satf_vdb_grid_destroy and the
 * voxels go with the last. NULL when out of memory. Scenes whose clusters
 * all name one file read it once this way, not once per cluster. */
satf_vdb_grid *satf_vdb_grid_share(const satf_vdb_grid *g);

/* Trilinear (OpenVDB BoxSampler) density at a world-space point. Outside the
 * active voxels, and for non-finite or absurdly distant points, it is the
 * grid's background value (0 for every grid a builder makes). Thread-safe. */
float satf_vdb_sample(const satf_vdb_grid *g, const float world_xyz[3]);

/* Samples n points (xyz holds n interleaved x,y,z triples) into out[n].
 * Thread-safe: each call uses its own tree accessor, so the renderer may
 * call it from many threads on one grid. */
void satf_vdb_sample_many(const satf_vdb_grid *g, size_t n, const float *xyz,
                          float *out);

/* World-space box enclosing every active voxel (voxel extents, not centres).
 * Returns 0 and sets lo = hi = 0 when the grid has no active voxels. */
int satf_vdb_bbox(const satf_vdb_grid *g, float lo[3], float hi[3]);

/* Edge length of a voxel in world units (the cube root of the voxel volume
 * when a file's voxels are not cubes). */
float satf_vdb_voxel_size(const satf_vdb_grid *g);

/* Sum over active voxels and tiles of density x voxel volume. */
double satf_vdb_total_mass(const satf_vdb_grid *g);

/* ---- Building ---------------------------------------------------------- */

/* An empty density grid with cubic voxels of edge voxel_size whose centres
 * lie at integer multiples of voxel_size. */
satf_status satf_vdb_builder_create(float voxel_size, satf_vdb_builder **out,
                                    satf_error *err);

/* Frees a builder (NULL is allowed). */
void satf_vdb_builder_destroy(satf_vdb_builder *b);

/* Adds an isotropic 3-D Gaussian of standard deviation sigma holding `mass`,
 * truncated at 3 sigma along each axis. Each voxel receives the Gaussian's
 * integral over the voxel (so sigma may be far below the voxel size) and the
 * truncated kernel is renormalised, so the grid's total mass grows by exactly
 * `mass`. Not thread-safe. Fails with SATF_ERR_ARGUMENT for non-finite input,
 * sigma <= 0, mass < 0 or a footprint over 256 voxels per axis. */
satf_status satf_vdb_builder_add_gaussian(satf_vdb_builder *b,
                                          const float center[3], float sigma,
                                          float mass, satf_error *err);

/* Adds the hair segment p0-p1 as the segment convolved with a 3-D Gaussian of
 * width sigma: its cross-section is the circular Gaussian
 * exp(-r^2 / (2 sigma^2)) of SATF sec. 3.3 and consecutive segments of a
 * strand join without seams. Total mass is mass_per_length x |p1 - p0|. */
satf_status satf_vdb_builder_add_tube(satf_vdb_builder *b, const float p0[3],
                                      const float p1[3], float sigma,
                                      float mass_per_length, satf_error *err);

/* Writes the density as a fog-volume FloatGrid named grid_name, through a
 * temporary file renamed into place only when every write, the flush, fsync
 * and close succeeded; otherwise SATF_ERR_IO with the reason (e.g. "No space
 * left on device"), the temporary file removed and any file already at path
 * left as it was. */
satf_status satf_vdb_builder_write(const satf_vdb_builder *b, const char *path,
                                   const char *grid_name, satf_error *err);

/* A readable copy of the density built so far; the builder stays usable. */
satf_status satf_vdb_builder_to_grid(const satf_vdb_builder *b,
                                     satf_vdb_grid **out, satf_error *err);

/* ---- Test support ------------------------------------------------------ */

/* Writes a .vdb holding a FloatGrid "density" (one voxel of value 1), an
 * Int32Grid "ids" and a Vec3SGrid "velocity", so the type checks of readers
 * can be exercised without another tool. */
satf_status satf_vdb_write_mixed_test_file(const char *path, satf_error *err);

/* density.h - the density level of the hierarchy (SATF sec. 3.1, 3.3): a
 * cluster's hair density, either procedural strands placed in the
 * cluster's normalised cross-section or an OpenVDB grid in world space, and
 * the density features (sec. 5.2) of every boundary sector of its shells. */

/* Grid nodes per side used to sample a sector's density for its features.
 * 16 (measured by tests/render/bench_lookup): at 8 the nodes along a
 * sector's phase are about a strand width apart (cluster_6a: 0.022 against
 * strands 0.03 wide), so a strand counts more or less by where it falls
 * between nodes: held-out error 7% above 16's at k = 4. 32, the database's
 * own grid, gains 2% more for 4x the time. */
#define SATF_SECTOR_GRID 16

typedef struct satf_strands satf_strands;

/* Places d->strands strands (seeded) in the unit disk of normalised
 * cross-section coordinates (x, y) = v (cos u, sin u), following d->layout.
 * Each strand drifts slowly along t so the density is not constant along
 * the cluster. */
satf_status satf_strands_create(const satf_scene_density *d, satf_strands **out,
                                satf_error *err);
void satf_strands_destroy(satf_strands *s);
int satf_strands_count(const satf_strands *s);
/* Position of strand i at t, in normalised cross-section coordinates. */
void satf_strands_position(const satf_strands *s, int i, float t, float xy[2]);

/* Density at normalised (x, y) at t: one circular Gaussian per strand of
 * peak 1/2 (coverage units, as in the HRIR database) times d->scale. */
float satf_strands_density(const satf_strands *s, float t, float x, float y);

/* Features of the (st + 1) x layers x su boundary sectors of a cluster, in
 * that order (index (i * layers + k) * su + j), 3 floats each. With a VDB
 * grid, sector nodes are mapped to world space through `instance` (4x4 row
 * major, may be NULL for identity) and sampled there; otherwise strands are
 * used. Runs on `threads` threads (0 = all). */
satf_status satf_sector_features(const satf_cluster *cluster,
                                 const satf_shell_params *shell,
                                 const satf_strands *strands,
                                 const satf_vdb_grid *vdb,
                                 const float *instance, int threads,
                                 float *features, satf_error *err);
/* The same on grid x grid nodes per sector (2 to 64); satf_sector_features
 * uses SATF_SECTOR_GRID. For measuring what the grid costs and changes. */
satf_status satf_sector_features_grid(const satf_cluster *cluster,
                                      const satf_shell_params *shell,
                                      const satf_strands *strands,
                                      const satf_vdb_grid *vdb,
                                      const float *instance, int grid,
                                      int threads, float *features,
                                      satf_error *err);

/* Where a cluster's own strands run at each boundary sector of its shells,
 * in satf_sector_features' order (3 floats a sector, in the cluster's
 * frame): the unit direction of the sum of the unit chords of the strands'
 * track segments (between two slices) that span the sector's t and pass
 * through its phase column or the two beside it, in any layer (so every
 * layer of a column gets the same direction); zero where no strand passes
 * or their chords cancel. Strands that
 * cross their cluster's trajectory, as a crown's do where they gather
 * towards a ponytail's tie, are shaded along their own course
 * (maps_fiber.c). Needs a "tracks" density (SATF_ERR_ARGUMENT otherwise);
 * runs on `threads` threads (0 = all). */
satf_status satf_sector_hair_directions(const satf_cluster *cluster,
                                        const satf_shell_params *shell,
                                        const satf_scene_density *density,
                                        int threads, float *dirs,
                                        satf_error *err);

#ifdef __cplusplus
}
#endif
#endif
