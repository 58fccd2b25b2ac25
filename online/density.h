/* density.h - the density level of the hierarchy (SATF sec. 3.1, 3.3): a
 * cluster's hair density, either procedural strands placed in the
 * cluster's normalised cross-section or an OpenVDB grid in world space, and
 * the density features (sec. 5.2) of every boundary sector of its shells. */
#ifndef SATF_ONLINE_DENSITY_H
#define SATF_ONLINE_DENSITY_H

#include "satf/cluster.h"
#include "satf/scene.h"
#include "satf/vdb.h"

/* Grid nodes per side used to sample a sector's density for its features. */
#define SATF_SECTOR_GRID 8

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

#endif
