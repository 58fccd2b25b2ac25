/* import_internal.h - the importer's stages, shared by the files of
 * online/import/ and its tests; satf/import.h is what other code uses.
 *
 * Turning strand hair (satf/import.h) into the SATF hierarchy
 * (Xu et al. 2006, sec. 3.1-3.3, "in case the hair model is given as strand
 * positions"): strands are grouped into clusters (k-means on resampled
 * strand shapes), each cluster gets a generalized cylinder fitted to its
 * strands (satf/geometry.h), clusters whose shapes agree after a similarity
 * transform share one prototype (macro-clusters), and the strands become
 * density: per cluster in its (t, v, u) coordinates, and for the whole
 * hairstyle as a world-space OpenVDB grid. Finally a scene file
 * (satf/scene.h, samples/README.md) is written.
 *
 * Owns: the clustering result (labels), satf_import_fit (one cluster's
 * fitted parameters and fit quality), satf_import_projection (strand points
 * in a cluster's coordinates), satf_import_macro (prototypes and
 * transforms), satf_import_density (a cluster's density grid) and the scene
 * writer's options. Every struct with pointers is freed by its *_free. */
#ifndef SATF_ONLINE_IMPORT_INTERNAL_H
#define SATF_ONLINE_IMPORT_INTERNAL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "satf/density.h"
#include "satf/geometry.h"
#include "satf/import.h"
#include "satf/scene.h"

/* The widest strand (a mean diameter, in units of the cluster radius
 * sqrt(mean A x mean B)) a cluster's shells can show: twice the widest
 * strand of the database's generalized sectors (offline/sector.c: Gaussians
 * of sigma up to 0.02 of the envelope radius, the mass of a disc 0.04
 * across). A cluster of wider strands is a few strands side by side that no
 * record holds (the shared ponytail's guides, 0.12-0.31 radii across, drew
 * as smooth scales: SSIM 0.59 against its strands); the adaptive clustering
 * splits it into single strands, which the renderer draws as themselves.
 * Dense hair stays in volumes (a generated curtain of 4,000 strands:
 * 0.04-0.06). */
#define SATF_IMPORT_SHELL_STRAND_WIDTH 0.08

/* The width (a diameter) of strands whose files give none, in units of
 * the hair's bounding-box diagonal: what the measuring reference draws
 * (Cycles' hair at a radius of 5e-4 of the diagonal), under a pixel when
 * the default camera frames the hair, as fibres are (the shared
 * ponytail's: 0.18 units, 0.6 pixels at 640x480). */
#define SATF_IMPORT_FIBRE_WIDTH 1e-3

/* Called now and then from the calling thread; may be NULL. */
typedef void (*satf_import_progress_fn)(void *ctx, size_t done, size_t total);

/* ---- Clustering (import_cluster.c) ------------------------------------ */

typedef struct satf_import_cluster_params {
  int clusters;   /* 1..SATF_IMPORT_MAX_CLUSTERS, or 0 = choose */
  int samples;    /* points each strand is resampled to, 2..256 */
  int iterations; /* Lloyd iterations at most, >= 1 */
  uint64_t seed;  /* k-means++ seeding */
  int threads;    /* 0 = all cores */
} satf_import_cluster_params;

satf_import_cluster_params satf_import_cluster_params_default(void);

/* Resamples strand i to `samples` points evenly spaced in arc length. */
void satf_import_resample(const satf_strand_set *s, int i, int samples,
                          float *out);

/* The cluster count chosen when none is given: the smallest power of two
 * (1..min(1024, strands / 4)) whose k-means RMS strand-to-centre distance is
 * at most 3% of the hairstyle's bounding-box diagonal, measured on a sample
 * of at most 4000 strands. */
satf_status satf_import_choose_clusters(const satf_strand_set *s,
                                        const satf_import_cluster_params *p,
                                        int *clusters, satf_error *err);

/* k-means on resampled strand shapes (k-means++ seeding, Lloyd iterations,
 * empty clusters re-seeded with the farthest strand). labels receives one
 * cluster index per strand; *n_clusters the count used (the given one, at
 * most the strand count, or the chosen one); rms (may be NULL) the RMS
 * distance of resampled points to their centre. Deterministic for a given
 * seed whatever the thread count. */
satf_status satf_import_kmeans(const satf_strand_set *s,
                               const satf_import_cluster_params *p, int *labels,
                               int *n_clusters, float *rms,
                               satf_import_progress_fn progress,
                               void *progress_ctx, satf_error *err);

/* Strand indices of cluster c, in order: *members is malloc'ed. */
satf_status satf_import_members(const int *labels, int n_strands, int c,
                                int **members, int *n_members, satf_error *err);

/* ---- Fitting the generalized cylinder (import_fit.c) ------------------ */

typedef struct satf_import_fit_params {
  int n_ctrl;       /* trajectory control points, 2..64 */
  int n_radius;     /* control values of A, B and twist, 1..64 */
  int samples;      /* points the mean strand is resampled to, >= n_ctrl */
  float coverage;   /* share of strand points the envelope encloses, (0, 1] */
  float min_radius; /* A and B are at least this (scene units), >= 0 */
} satf_import_fit_params;

satf_import_fit_params satf_import_fit_params_default(void);

/* How well one fitted cylinder follows its member strands, the measures
 * the adaptive refinement (import_refine.c) holds to a tolerance. Each
 * [3] is p50, p90 and max over the member points (scene units).
 * trajectory: distance of a point to T(t) at its closest t. surface:
 * distance of a point to the envelope along its ray from the trajectory
 * in the cross-section, |r - r / v| (exact for a round section); outside:
 * the same for points outside the envelope, 0 inside. area_per_strand:
 * mean envelope area pi A B over t per member strand (how much empty
 * volume the cluster adds: the envelope inflated to hold diverging strands
 * shows here). diameter: twice the mean larger half-axis; aspect: trajectory
 * length over diameter (below 1 a cluster renders as a ring). direction:
 * the angle, in degrees, between each strand segment and the trajectory
 * (p50, p90, max over the segments; 0 for a tuft, drawn as its strands):
 * shells shade their hair along the trajectory, so a cluster whose strands
 * cross it is shaded with other highlights than its strands have. */
typedef struct satf_import_fit_measures {
  float trajectory[3];
  float surface[3];
  float outside[3];
  float direction[3];
  float area_per_strand;
  float diameter;
  float aspect;
} satf_import_fit_measures;

/* One cluster's generalized cylinder (SATF eq. 1-2) and how well it fits. */
typedef struct satf_import_fit {
  int n_ctrl;
  float *traj; /* n_ctrl * 3 */
  int n_radius;
  float *a, *b, *twist; /* n_radius each: A, B along n1, n2 turned by theta */
  float *spread;       /* n_radius x 3: second moments xx, xy, yy of the points'
                          offsets in the untwisted normal-plane frame (n1, n2 of
                          satf_cluster_frame), scene units^2 */
  int strands;         /* member strands */
  size_t points;       /* their points */
  size_t inside;       /* points inside the envelope (v <= 1) */
  double distance_sum; /* sum of point-to-trajectory distances */
  float length;        /* arc length of the trajectory */
  /* how well the cylinder follows its strands (satf_import_fit_cluster):
   * p50, p90 and max over the member points */
  satf_import_fit_measures measures;
  /* density estimates (filled by satf_import_estimate_density) */
  float strand_width; /* diameter, in units of the cluster radius */
  float radius;       /* sqrt(mean a * mean b), scene units */
  satf_scene_layout layout;
  float gradient; /* for SATF_SCENE_LAYOUT_GRADIENT */
  float core;     /* the shells' hollow core, v: 3% of the points lie
                     inside (satf_import_choose_shell); 0.4 until measured */
  /* the members as tracks (satf_import_fit_tracks; the scene density type
   * "tracks", fields as in satf_scene_density); n_tracks 0: none */
  int track_slices, n_tracks;
  int *track_first, *track_count;
  float *track_xy, *track_ends;
  /* which member (an index into the members fitted) each track follows;
   * and, filled by satf_import_width_from_thickness where a cluster has
   * two or more tracks, each one's strand width in cluster radii (NULL:
   * all at strand_width) */
  int *track_member;
  float *track_width;
  /* the members' own curl (satf_import_members_curl), scene units; > 0:
   * the scene gives the cluster the strands' angle to its trajectory
   * (satf_scene_density.curl) */
  float curl;
} satf_import_fit;

/* Fits the cluster of the strands `members`: the trajectory is the
 * least-squares cubic B-spline through the members' mean strand (for fur,
 * short straight parallel strands whose roots cover a patch wider than a
 * strand is long and whose points reach 1.25x further along their
 * direction: through the least-squares parabola through all their points
 * at their places along that direction, a tuft from the first roots to the
 * last tips; such a fur sheet also keeps one twist and an envelope that
 * tapers slowly, so its hair runs along it; with fewer
 * control points, down to 4, where they would swing more than half the
 * data's diagonal outside it, so out->n_ctrl may be below p->n_ctrl). The twist
 * theta turns the geometry's ellipse away from the rotation-minimising
 * axes (SATF eq. 1 as satf/geometry.h reads it), so theta(t) is the
 * orientation of the principal axes of the points' spread in the normal
 * plane, unwrapped along t (modulo a quarter turn, A and B trading places;
 * where the spread is round it follows the strands' winding about the
 * trajectory), and A and B come from the spread along the turned axes (the
 * second moments at each control value, weighted by its B-spline basis
 * function), scaled together so the envelope encloses `coverage` of the
 * points. */
satf_status satf_import_fit_cluster(const satf_strand_set *s,
                                    const int *members, int n_members,
                                    const satf_import_fit_params *p,
                                    satf_import_fit *out, satf_error *err);
void satf_import_fit_free(satf_import_fit *fit);

/* The satf_cluster of a fit (caller destroys). */
satf_status satf_import_fit_cluster_create(const satf_import_fit *fit,
                                           satf_cluster **out, satf_error *err);

/* The point of the trajectory closest to p: its parameter *t, the distance,
 * and p's offset along the ellipse's axes at *t (n1, n2 of
 * satf_cluster_section, turned by the twist). */
void satf_import_project_point(const satf_cluster *cluster, const float p[3],
                               float *t, float *distance, float xy[2]);

/* Every member strand's points in the cluster's coordinates: t, and the
 * normalised cross-section position (x, y) = v (cos u, sin u) (SATF eq. 1,
 * so v = 1 on the envelope). */
typedef struct satf_import_projection {
  int n_strands;
  size_t *offset; /* n_strands + 1 */
  float *txy;     /* 3 per point */
} satf_import_projection;

satf_status satf_import_project(const satf_strand_set *s, const int *members,
                                int n_members, const satf_cluster *cluster,
                                satf_import_projection *out, satf_error *err);
void satf_import_projection_free(satf_import_projection *p);
/* Position (x, y) of projected strand i where it crosses t; 0 when it does
 * not reach t. */
int satf_import_projection_at(const satf_import_projection *p, int i, float t,
                              float xy[2]);

/* ---- Adaptive clustering (import_refine.c) ----------------------------- */

/* When a fitted cluster is good enough (satf_import_fit_measures): the p90
 * point-to-trajectory and point-to-surface distances at most `tolerance`,
 * the envelope area per member strand at most area_ratio x spacing^2 (a
 * cluster holding diverging or sparse strands is mostly empty), and
 * length / diameter at least min_aspect (a cluster shorter than it is wide
 * renders as a ring). A cluster that fails is first given more trajectory
 * control points (up to max_ctrl) when its trajectory is what fails, else
 * split in two by 2-means on its strands' shapes, until every cluster
 * passes, holds one strand, or max_clusters is reached (the worst split
 * first). */
typedef struct satf_import_refine_params {
  float tolerance;  /* scene units, > 0 */
  float spacing;    /* the strands' root spacing, scene units, >= 0 */
  float area_ratio; /* 0: no area limit */
  float min_aspect; /* 0: no aspect limit */
  int initial;      /* k-means clusters to start from, >= 1 */
  int max_clusters; /* 1..SATF_IMPORT_MAX_CLUSTERS */
  int max_ctrl;     /* n_ctrl..64 */
  int threads;      /* 0 = all cores */
} satf_import_refine_params;

/* The parameters of quality q for the strands s: tolerance a fraction of
 * the hairstyle's bounding-box diagonal (draft 4%, default 2%, high 1%)
 * unless tolerance > 0 gives it in scene units or tolerance < 0 gives the
 * fraction (-tolerance). */
satf_import_refine_params
satf_import_refine_params_for(const satf_strand_set *s, satf_import_quality q,
                              double tolerance);

/* p50, p90 and max of v[0..n) (sorted in place; import_fit.c), as the fit
 * measures take them. */
void satf_import_percentiles(float *v, size_t n, float out[3]);

/* Strand indices grouped by cluster (labels: each of the n strands' of k
 * clusters): cluster c's are idx[off[c]..off[c+1]). Returns 0, or -1 out
 * of memory (free what was made with satf_import_groups_free). */
typedef struct satf_import_groups {
  int *off, *idx;
} satf_import_groups;
int satf_import_groups_build(const int *labels, int n, int k,
                             satf_import_groups *g);
void satf_import_groups_free(satf_import_groups *g);

/* How far strand i curls about its own course (import_curl.c): the p90
 * distance of its points, 33 evenly along it, to their moving average over
 * half the strand; about a helix's radius, near 0 for straight or
 * wavy hair. */
float satf_import_strand_curl(const satf_strand_set *s, int i);

/* The median of curl[] over the n members (0 for fewer than two). */
float satf_import_members_curl(const float *curl, const int *members, int n);

/* Sets fits[c].curl for each of the n clusters (labels: each strand's),
 * on `threads` threads (0: all cores). Returns 0, or -1 out of memory. */
int satf_import_fits_curl(const satf_strand_set *s, const int *labels,
                          satf_import_fit *fits, int n, int threads);

/* How much of a tolerance a fit uses: the largest of its measures over its
 * limit (<= 1: it passes). */
float satf_import_fit_score(const satf_import_fit *fit,
                            const satf_import_refine_params *rp);

/* Clusters the strands adaptively: k-means with rp->initial clusters (seed
 * from cp), then fit, check and split as satf_import_refine_params says.
 * Where the strands have a thickness, half their mean thickness caps
 * fp->min_radius (a cluster of one sparse strand is as thin as it is).
 * labels (one per strand) and *n_clusters receive the result; *fits a
 * malloc'ed array of *n_clusters fits, density estimated (as
 * satf_import_fit_all leaves them): free each and the array. Deterministic
 * whatever the thread count. */
satf_status satf_import_refine(const satf_strand_set *s,
                               const satf_import_cluster_params *cp,
                               const satf_import_refine_params *rp,
                               const satf_import_fit_params *fp, int *labels,
                               int *n_clusters, satf_import_fit **fits,
                               satf_import_progress_fn progress,
                               void *progress_ctx, satf_error *err);

/* ---- The fit report (import_report.c) ---------------------------------- */

void satf_import_fit_stats_compute(const satf_import_fit *fits, int n,
                                   const satf_import_refine_params *rp,
                                   satf_import_fit_stats *out);
/* The report lines of the summary (indented to match it); warns about
 * clusters shorter than their diameter. */
void satf_import_fit_stats_print(FILE *out, const char *prog,
                                 const satf_import_fit_stats *st);
/* One line per cluster (strands, length, diameter, aspect, area per strand,
 * p50/p90/max of the trajectory, surface and outside distances and of the
 * strands' angle to the trajectory) as
 * tab-separated text with a header, written atomically to path. */
satf_status satf_import_write_fit_report(const char *path,
                                         const satf_import_fit *fits, int n,
                                         satf_error *err);

/* ---- Density (import_density.c) --------------------------------------- */

/* Fills fit->strand_width (twice the mean nearest-neighbour spacing of the
 * strands in the normalised cross-section, so the file's strands fill the
 * cluster as the many more strands of real hair would), fit->radius, and
 * the layout: "gradient" with the slope g of 1 + g (v - 1/2) when the
 * strands' mean v says |g| >= 0.3, else "uniform"; and fit->core, the v
 * below which only a few of the points lie (the shells hold the rest). */
void satf_import_estimate_density(const satf_import_projection *proj,
                                  satf_import_fit *fit);
/* The members as tracks (import_tracks.c): where each crosses evenly
 * spaced t slices in the normalised cross-section, root slice to tip
 * slice; called by satf_import_estimate_density. Without memory the fit
 * keeps no tracks (the procedural density stands in). */
void satf_import_fit_tracks(const satf_import_projection *proj,
                            satf_import_fit *fit);

/* Strands without a thickness in their file (import_spacing.c): each
 * strand's width (a diameter) from the hairstyle's own spacing, before any
 * clustering: twice the median, over its points (root and tip left out),
 * of the distance to the nearest segment of another strand, kept between
 * a quarter and twice the hairstyle's median (a strand with no other within
 * a median segment length gets the median). width holds one float per
 * strand. */
satf_status satf_import_spacing_widths(const satf_strand_set *s, int threads,
                                       float *width, satf_error *err);

/* When the strands carry a thickness: fit->strand_width becomes the
 * members' mean diameter over the cluster radius (0.005..2), and with two
 * or more tracks each track's own (track_width), so the
 * density is that of the file's strands as they are drawn, not of strands
 * widened to fill the cluster. A one-strand cluster narrower than its
 * strand grows round it instead (A and B up, its tracks down by as much:
 * the strand stays in place) and takes strand_width 2. Nothing changes
 * without thickness (satf_import_run gives strands without one a hair
 * fibre's width, SATF_IMPORT_FIBRE_WIDTH). */
void satf_import_width_from_thickness(const satf_strand_set *s,
                                      const int *members, int n,
                                      satf_import_fit *fit);

/* A cluster's density in its own coordinates (SATF sec. 3.3): nt slices at
 * t = (i + 0.5) / nt, each an n x n grid over normalised (x, y) in
 * [-extent, extent]^2, in which every strand crossing the slice adds a
 * circular Gaussian of standard deviation sigma (normalised units) and
 * mass pi sigma^2 (coverage units: a lone strand peaks near 1/2). */
typedef struct satf_import_density {
  int nt, n;
  float extent, sigma;
  float *values; /* nt * n * n, [(i * n + y) * n + x] */
} satf_import_density;

satf_status satf_import_cluster_density(const satf_import_projection *proj,
                                        int nt, int n, float extent,
                                        float sigma, satf_import_density *out,
                                        satf_error *err);
void satf_import_density_free(satf_import_density *d);
/* Integral of slice i: sum of values x cell area. */
double satf_import_density_slice_mass(const satf_import_density *d, int i);

/* World-space Gaussian width of a cluster's strands: half the strand width
 * times the cluster radius. */
float satf_import_world_sigma(const satf_import_fit *fit);
/* The scale of a cluster's density (satf_scene_density.scale) for the
 * default database's records (satf_trace_params_default, satf_sector_
 * shape_default): as opaque on average as strands of the density's width,
 * 4 / (pi width extinction) but at least 1, times the shell layers' depth
 * over the records' (a layer takes one record's alpha, traced through the
 * canonical sector's depth of 0.2 cluster radii). */
float satf_import_density_scale(float strand_width, float layer_depth);

/* The whole hairstyle's density in world space: every segment of strand i
 * is a tube of width satf_import_world_sigma(fits[labels[i]]) (half the
 * file's thickness instead where the set has thickness) and mass pi
 * sigma^2 per unit length (coverage units, as the per-cluster grids). */
satf_status satf_import_build_vdb(const satf_strand_set *s, const int *labels,
                                  const satf_import_fit *fits, float voxel,
                                  satf_vdb_builder **out,
                                  satf_import_progress_fn progress,
                                  void *progress_ctx, satf_error *err);

/* ---- Macro-clusters (import_macro.c) ---------------------------------- */

/* Clusters whose shapes match within `tolerance` after a similarity
 * transform share one prototype (SATF sec. 3.1). */
typedef struct satf_import_macro {
  int n_clusters;
  int n_macro;
  int *prototype;        /* n_macro cluster indices */
  int *macro_of;         /* n_clusters: the macro-cluster of each cluster */
  float *transform;      /* n_clusters x 16 row-major: prototype -> cluster */
  float *residual;       /* n_clusters: shape mismatch / prototype length */
  size_t bytes_separate; /* cluster parameters stored one by one */
  size_t bytes_shared;   /* prototypes + one transform per instance */
} satf_import_macro;

/* The best similarity transform (scale s, rotation R, translation) taking n
 * points `from` onto `to` in the least-squares sense (Horn's quaternion
 * method; R is a proper rotation). m receives the 4x4 row-major matrix;
 * returns the RMS residual. */
double satf_import_similarity(const double *from, const double *to, int n,
                              double m[16]);

/* Greedy grouping: each cluster not yet grouped becomes a prototype and
 * takes every later ungrouped cluster whose trajectory, after the best
 * similarity transform, lies within tolerance x the prototype's length
 * (RMS over 16 samples along t) and whose strands' spread in the normal
 * plane (second moments as a 3-D tensor, carried by the transform) matches
 * within 6 x tolerance relative, on average over t.
 * tolerance <= 0 makes every cluster its own prototype. The comparisons
 * grow as n^2 (seconds for thousands of clusters): progress (may be NULL)
 * is called with the clusters grouped or made prototypes so far. */
satf_status satf_import_find_macro(const satf_import_fit *fits, int n,
                                   float tolerance,
                                   satf_import_progress_fn progress,
                                   void *progress_ctx, satf_import_macro *out,
                                   satf_error *err);
void satf_import_macro_free(satf_import_macro *m);

/* ---- Scene file (import_scene.c) -------------------------------------- */

typedef struct satf_import_scene_options {
  const char *vdb_file;    /* density grid to name, or NULL: procedural */
  const char *vdb_grid;    /* grid name, default "density" */
  const char *database;    /* written as given, or NULL */
  const char *description; /* or NULL */
  int width, height;       /* image size, 0 = 640 x 480 */
  uint64_t seed;           /* procedural placement seeds start here */
  const char *mesh_file;   /* an opaque head mesh to list, or NULL */
  /* the box the camera frames (the strands' bounds, so that the view does
   * not change with the clustering or --quality), or NULL: the clusters' */
  const float *frame_lo, *frame_hi;
} satf_import_scene_options;

/* Shell sampling chosen for a fitted cluster (import_shell.c): 3..6 layers
 * (more for more strands), st from the trajectory length over the radius
 * (8..64), su 16..32 (more for flatter ellipses). */
satf_scene_shell satf_import_choose_shell(const satf_import_fit *fit);

/* The scene (satf/scene.h) of the fitted clusters: one macro-cluster per
 * prototype with one instance per member cluster (macro may be NULL: one
 * macro-cluster per cluster), a camera framing the hair and a key and a
 * fill light. path is where it will be written (it names the scene and its
 * directory is the base of the relative paths in o), or NULL: paths are
 * held as given. */
satf_status satf_import_scene_build(const satf_import_fit *fits, int n,
                                    const satf_import_macro *macro,
                                    const satf_import_scene_options *o,
                                    const char *path, satf_scene **out,
                                    satf_error *err);
/* That scene as JSON text (malloc'ed, NUL-terminated; satf_scene_to_json). */
satf_status satf_import_scene_json(const satf_import_fit *fits, int n,
                                   const satf_import_macro *macro,
                                   const satf_import_scene_options *o,
                                   char **json, satf_error *err);
/* The same, written to path (satf_scene_write). */
satf_status satf_import_write_scene(const char *path,
                                    const satf_import_fit *fits, int n,
                                    const satf_import_macro *macro,
                                    const satf_import_scene_options *o,
                                    satf_error *err);

/* ---- Publishing a scene with its side files (import_publish.c) --------- */

/* A file the scene names that the import writes beside it (the density
 * grid, the strands). It is published under its base name with 8 hex
 * digits of its bytes' FNV-1a hash before the extension ("out/hair.vdb"
 * becomes "out/hair-1a2b3c4d.vdb"), so a new import never replaces a file
 * the scene on disk names. */
typedef satf_status (*satf_import_side_write_fn)(const char *path, void *ctx,
                                                 satf_error *err);
typedef struct satf_import_side {
  const char *base;                /* the name asked for */
  satf_import_side_write_fn write; /* writes the whole file at path */
  void *ctx;
  char staging[4096];   /* BASE.tmp-PID while staged, "" otherwise */
  char published[4096]; /* the name it is published under ("" before) */
  int created;          /* 1 once renamed to a new name (0: the same bytes
                           were already there under that name) */
} satf_import_side;

/* Writes side->base's file through side->write into its staging file
 * BASE.tmp-PID (after removing those of dead processes: what a kill
 * left) and hashes it, which names it (side->published). Nothing is
 * published yet: satf_import_publish_scene does that. */
satf_status satf_import_stage_side(satf_import_side *side, satf_error *err);

/* Removes what sides staged or published (an import that gives up). */
void satf_import_discard_sides(satf_import_side *sides, int n_sides);

/* Publishes a scene with its staged side files as one unit: the side
 * files are renamed to their published names and reach the disk, then
 * scene is written to path (satf_scene_write: renamed into place last).
 * Then the side files the replaced scene at path named are removed when
 * the new scene does not name them and they are published side files
 * (STEM-XXXXXXXX.EXT whose XXXXXXXX is the hash of their bytes: an import
 * made them). If anything fails, the old scene stays as it was, with its
 * files, and the new side files it does not name are removed. A run killed
 * at any point leaves the old scene with its files or the new one with
 * its own. */
satf_status satf_import_publish_scene(const satf_scene *scene, const char *path,
                                      satf_import_side *sides, int n_sides,
                                      satf_error *err);

/* ---- Steps of the whole import (import_steps.c, import_sequence.c) ----- */

/* Whether importing `points` strand points fits o's memory budget; if
 * not, an error "WHAT: N strand points would need about X to import ...,
 * over the memory budget of Y: ...". Checked before follow strands are
 * made (naming the count that fits) and after the inputs are read, before
 * anything grows with them. */
satf_status satf_import_check_budget(const satf_import_options *o,
                                     const char *what, size_t points,
                                     satf_error *err);

/* Reads one strand file by its signature (or, where the bytes have none,
 * its name's extension; TressFX gets o's follow strands) and moves it into
 * the scene's axes as o's up_z and hair_* say. */
satf_status satf_import_read_strands(const char *path,
                                     const satf_import_options *o,
                                     satf_strand_set **out, satf_error *err);
/* The same; *followers receives the follow strands added per TressFX
 * guide (satf_import_follow_count), -1 for the other formats. */
satf_status satf_import_read_strands_followed(const char *path,
                                              const satf_import_options *o,
                                              satf_strand_set **out,
                                              int *followers, satf_error *err);

/* Follow strands per guide when the header names none: what AMD's TressFX
 * loader (TressFXAsset) grows around each guide unless the engine asks
 * otherwise, so a guide file draws as dense as in TressFX's own viewer. */
#define SATF_IMPORT_TFX_FOLLOW 4

/* Followers per TressFX guide: --follow's (o->follow >= 0), else the
 * header's numFollowStrandsPerGuide when it names some, else
 * SATF_IMPORT_TFX_FOLLOW. */
int satf_import_follow_count(const satf_import_options *o, int header_follow);

/* Fits every cluster of labels (in parallel) and estimates its density:
 * fits[c] for c < n_clusters. On failure the message is the first
 * cluster's that failed. */
satf_status satf_import_fit_all(const satf_strand_set *s, const int *labels,
                                int n_clusters, const satf_import_fit_params *p,
                                int threads, satf_import_fit *fits,
                                satf_import_progress_fn progress,
                                void *progress_ctx, satf_error *err);

/* Re-fits every frame of the sequence o (inputs[0] with frames first..last)
 * onto the clusters of labels (the same member strands; each frame must
 * keep n_strands strands) and adds the fits to scene as keys of its
 * macro-clusters (one cluster each: macro), after making it animated. */
satf_status satf_import_sequence_keys(satf_scene *scene,
                                      const satf_import_options *o,
                                      const int *labels, int n_strands,
                                      const satf_import_fit_params *p,
                                      const satf_import_macro *macro,
                                      satf_error *err);

#endif
