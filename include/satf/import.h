/* import.h - strand hair into satf scenes (online/import/): strand sets and
 * the .hair/.tfx readers and writers, clustering, fitting, macro-clusters,
 * density and the scene the importer writes.
 *
 * ---- Strands ----
 * Hair given as strands (polylines), the way artists and
 * simulators store it, and the readers and writers of two common strand
 * formats: Cem Yuksel's cyHair `.hair` and AMD TressFX `.tfx` (3.x and 4.x
 * layouts). The byte layouts are documented in the project's data README.
 *
 * Owns satf_strand_set, an immutable-after-build set of strands: strand i
 * has satf_strand_set_points(s, i) points (>= 2, i.e. at least one segment)
 * stored as x y z floats, and optionally one thickness per point.
 *
 * Every reader checks the header against the file length before it
 * allocates anything, and rejects truncated files, counts that do not add
 * up, absurd counts, strands without a segment and non-finite points with a
 * message naming the file and the reason. The parse functions take the
 * file's bytes (what the fuzz targets feed them); the read functions load a
 * file and parse it. */
#ifndef SATF_IMPORT_H
#define SATF_IMPORT_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "satf/density.h"
#include "satf/geometry.h"
#include "satf/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Limits beyond which a count is called absurd rather than allocated. */
#define SATF_STRANDS_MAX_STRANDS (1u << 26) /* 67 M strands */
#define SATF_STRANDS_MAX_POINTS (1u << 28)  /* 268 M points in a set */
#define SATF_STRANDS_MAX_PER_STRAND 65536   /* points in one strand */
#define SATF_STRANDS_MAX_FOLLOW 1024        /* follow strands per guide */
#define SATF_STRANDS_MAX_FILE_BYTES (4ull << 30)

typedef struct satf_strand_set satf_strand_set;

/* Copies n_strands strands: strand i has counts[i] points (>= 2), taken in
 * order from points (3 floats each). thickness (one per point) may be NULL.
 * Rejects non-finite values and absurd counts. */
satf_status satf_strand_set_create(int n_strands, const int *counts,
                                   const float *points, const float *thickness,
                                   satf_strand_set **out, satf_error *err);
void satf_strand_set_destroy(satf_strand_set *s);

/* A new set holding the strands of a followed by those of b (for importing
 * several files into one scene). Thickness is kept only when both have it. */
satf_status satf_strand_set_concat(const satf_strand_set *a,
                                   const satf_strand_set *b,
                                   satf_strand_set **out, satf_error *err);

int satf_strand_set_count(const satf_strand_set *s);
size_t satf_strand_set_point_count(const satf_strand_set *s);
/* Points of strand i and their count. */
const float *satf_strand_set_strand(const satf_strand_set *s, int i,
                                    int *n_points);
int satf_strand_set_points(const satf_strand_set *s, int i);
/* Thickness of the points of strand i, or NULL when the set has none. */
const float *satf_strand_set_thickness(const satf_strand_set *s, int i);
/* Axis-aligned bounds of every point. */
void satf_strand_set_bounds(const satf_strand_set *s, float lo[3], float hi[3]);
/* Polyline length of strand i. */
float satf_strand_set_length(const satf_strand_set *s, int i);

/* ---- cyHair .hair ------------------------------------------------------ */

satf_status satf_hair_parse(const void *data, size_t size, const char *name,
                            satf_strand_set **out, satf_error *err);
satf_status satf_hair_read(const char *path, satf_strand_set **out,
                           satf_error *err);
/* Writes segments, points and (when the set has them) thickness arrays,
 * through a temporary file renamed into place. */
satf_status satf_hair_write(const char *path, const satf_strand_set *s,
                            satf_error *err);

/* ---- TressFX .tfx ------------------------------------------------------ */

typedef struct satf_tfx_info {
  float version;        /* as stored: 3.x or 4.x */
  int guides;           /* strands in the file */
  int vertices;         /* vertices per strand */
  int follow_per_guide; /* 3.x header's numFollowStrandsPerGuide; 4.x: 0 */
  int both_ends_immovable;
} satf_tfx_info;

/* Parses the guide strands of a .tfx; info may be NULL. */
satf_status satf_tfx_parse(const void *data, size_t size, const char *name,
                           satf_tfx_info *info, satf_strand_set **out,
                           satf_error *err);
satf_status satf_tfx_read(const char *path, satf_tfx_info *info,
                          satf_strand_set **out, satf_error *err);
/* Writes s (every strand with the same point count) as a TressFX 3.0
 * (major_version 3, recording follow_per_guide) or 4.0 (major_version 4,
 * float4 positions with w = 1) file. */
satf_status satf_tfx_write(const char *path, const satf_strand_set *s,
                           int major_version, int follow_per_guide,
                           satf_error *err);

/* Follow strands as TressFX generates them around its guides: each
 * follower copies its guide, offset at the root by a random point of the
 * disk of `radius` in the root's normal plane; the offset is carried along
 * the guide by parallel transport and grows linearly to (1 +
 * tip_separation) times at the tip. */
typedef struct satf_follow_params {
  int count;            /* followers per guide, 0..SATF_STRANDS_MAX_FOLLOW */
  float radius;         /* root offset radius, scene units, >= 0 */
  float tip_separation; /* >= 0 */
  uint64_t seed;
} satf_follow_params;

/* A new set: each guide followed by its `count` followers. */
satf_status satf_strand_set_add_follow(const satf_strand_set *guides,
                                       const satf_follow_params *p,
                                       satf_strand_set **out, satf_error *err);
/* The same, calling progress(ctx, guides done, guides) now and then (it
 * may be NULL): 15 M points take seconds. */
satf_status satf_strand_set_add_follow_progress(
    const satf_strand_set *guides, const satf_follow_params *p,
    void (*progress)(void *ctx, size_t done, size_t total), void *progress_ctx,
    satf_strand_set **out, satf_error *err);

/* Mean distance between each strand's root and the nearest other root: the
 * scale of a sensible follow radius. 0 for fewer than two strands. */
float satf_strand_set_root_spacing(const satf_strand_set *s);

/* ---- PLY strands (strands_ply*.c) --------------------------------------- */

/* A `vertex` element with x, y, z (other properties skipped) and either a
 * strand element (`strand`, `strands`, `hair` or `curve`) with each
 * strand's point count (property `vertex_count`, `vertices`,
 * `num_vertices`, `nverts`, `num_points`, `points` or `count`) or segment
 * count (`segments`, `num_segments`, `segment_count`), the strands' points
 * in vertex order; or an `edge` element (`vertex1`, `vertex2`) chained into
 * polylines, each from its lower-numbered end. ascii,
 * binary_little_endian and binary_big_endian. Strands of one point are
 * skipped; branching or looping edges are refused. */
satf_status satf_ply_parse(const void *data, size_t size, const char *name,
                           satf_strand_set **out, satf_error *err);
satf_status satf_ply_read(const char *path, satf_strand_set **out,
                          satf_error *err);

/* ---- USC-HairSalon .data (strands_usc.c) -------------------------------- */

/* int32 strand count, then per strand an int32 point count and float32
 * x, y, z per point, little-endian, nothing after. Strands of fewer than
 * two points (the dataset marks bald scalp with one-point strands) are
 * skipped, as the dataset's own loader does. */
satf_status satf_usc_parse(const void *data, size_t size, const char *name,
                           satf_strand_set **out, satf_error *err);
satf_status satf_usc_read(const char *path, satf_strand_set **out,
                          satf_error *err);

/* ---- Which format a strand file is (strands_detect.c) ------------------- */

typedef enum satf_strands_format {
  SATF_STRANDS_UNKNOWN,
  SATF_STRANDS_HAIR, /* "HAIR" */
  SATF_STRANDS_TFX,  /* a TressFX version 1..6 in the first float */
  SATF_STRANDS_PLY,  /* "ply" line */
  SATF_STRANDS_USC   /* strand and point counts that fill the file exactly */
} satf_strands_format;

/* The format the bytes say, or UNKNOWN. */
satf_strands_format satf_strands_detect(const void *data, size_t size);
/* The format a file name's extension names (.hair .tfx .ply .data). */
satf_strands_format satf_strands_format_of_name(const char *path);
/* "cyHair", "TressFX", "PLY", "USC-HairSalon .data" or "unknown". */
const char *satf_strands_format_name(satf_strands_format f);

/* import.h - turning strand hair (satf/strands.h) into the SATF hierarchy
 * (Xu et al. 2006, sec. 3.1-3.3, "in case the hair model is given as strand
 * positions"): strands are grouped into clusters (k-means on resampled
 * strand shapes), each cluster gets a generalized cylinder fitted to its
 * strands (satf/cluster.h), clusters whose shapes agree after a similarity
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

#define SATF_IMPORT_MAX_CLUSTERS 8192

/* The widest strand (a mean diameter, in units of the cluster radius
 * sqrt(mean A x mean B)) a cluster's shells can show: twice the widest
 * strand of the database's generalized sectors (offline/sector.c: Gaussians
 * of sigma up to 0.02 of the envelope radius, the mass of a disc 0.04
 * across). A cluster of wider strands is a few strands side by side that no
 * record holds (the shared ponytail's guides, 0.12-0.31 radii across, drew
 * as smooth scales: SSIM 0.59 against its strands); the adaptive clustering
 * splits it into single strands, which the renderer draws as themselves
 * (issue 10 item 4). Dense hair stays in volumes (a generated curtain of
 * 4,000 strands: 0.04-0.06). */
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
 * length over diameter (below 1 a cluster renders as a ring). */
typedef struct satf_import_fit_measures {
  float trajectory[3];
  float surface[3];
  float outside[3];
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

/* The user's knob: how closely clusters follow their strands. */
typedef enum satf_import_quality {
  SATF_IMPORT_QUALITY_DEFAULT = 0, /* what zeroed options mean */
  SATF_IMPORT_QUALITY_DRAFT,
  SATF_IMPORT_QUALITY_HIGH
} satf_import_quality;

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

/* The clusters' fit measures summarised: for each measure the p50, p90 and
 * max over clusters of the clusters' own p90 (area and aspect: of their
 * value), the worst cluster of each, and the clusters that break the
 * limits. */
typedef struct satf_import_fit_stats {
  int clusters;
  float trajectory[3], surface[3], outside[3]; /* over clusters' p90 */
  float area_per_strand[3];
  float aspect[3]; /* p50, p10 and min: low is bad */
  int worst_trajectory, worst_aspect;
  int rings;       /* clusters shorter than their diameter, drawn as shells */
  int over;        /* clusters over the tolerance (when one was given) */
  int single;      /* clusters of one strand */
  int as_strands;  /* clusters the renderer draws as their strands by
                      default (satf_scene_tracks_as_strands) */
  int tufts;       /* those of them with more than SATF_SCENE_SPARSE_STRANDS
                      strands: tufts of short strands */
  float tolerance; /* 0: none */
  /* strands in all clusters, and in those drawn as shells */
  long long strands, shell_strands;
} satf_import_fit_stats;

void satf_import_fit_stats_compute(const satf_import_fit *fits, int n,
                                   const satf_import_refine_params *rp,
                                   satf_import_fit_stats *out);
/* The report lines of the summary (indented to match it); warns about
 * clusters shorter than their diameter. */
void satf_import_fit_stats_print(FILE *out, const char *prog,
                                 const satf_import_fit_stats *st);
/* One line per cluster (strands, length, diameter, aspect, area per strand,
 * p50/p90/max of the trajectory, surface and outside distances) as
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
 * tolerance <= 0 makes every cluster its own prototype. */
satf_status satf_import_find_macro(const satf_import_fit *fits, int n,
                                   float tolerance, satf_import_macro *out,
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

/* Shell sampling chosen for a fitted cluster: 3..6 layers (more for more
 * strands), st from the trajectory length over the radius (8..64), su
 * 16..32 (more for flatter ellipses). */
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

/* ---- The whole import (import_run.c, import_sequence.c) ---------------- */

#define SATF_IMPORT_MAX_INPUTS 64

/* The importer's memory estimate: bytes per strand point at its peak (the
 * points, their resampled copies, projections and labels, and the density
 * grid's voxels at the default voxel size: measured 40-65 bytes a point on
 * 0.3 M points, doubled), and the budget it is held to unless the command
 * line raises it. Work grows with the points too, so the budget also keeps
 * an import to minutes. */
#define SATF_IMPORT_BYTES_PER_POINT 128
#define SATF_IMPORT_DEFAULT_BUDGET 2e9 /* bytes: 2 GB */

/* What satf-import's command line asks for. */
typedef struct satf_import_options {
  const char *inputs[SATF_IMPORT_MAX_INPUTS];
  int n_inputs;
  const char *output; /* the scene file */
  /* also write the density grid, published as PATH-XXXXXXXX.vdb (see
   * satf_import_stage_side), or NULL */
  const char *vdb;
  const char *database; /* named in the scene (relative to it), or NULL */
  const char *mesh;     /* a head mesh, checked and named in the scene */
  /* 1: no strands file; else the strands (scene coordinates) are written
   * as SCENE-STEM.strands-XXXXXXXX.hair beside the scene and named by its
   * "strands" key */
  int no_strands;
  /* where the mesh goes: T(translate) R(axis, angle) S(scale), as a scene
   * mesh's "transform" (identity by default) */
  double mesh_translate[3], mesh_axis[3], mesh_angle_deg, mesh_scale[3];
  long clusters; /* 0: chosen from the data */
  /* adaptive clustering (clusters == 0): the quality and a tolerance in
   * scene units (> 0) or as a fraction of the hair's diagonal (< 0: -f) */
  satf_import_quality quality;
  double tolerance;
  const char *fit_report; /* per-cluster fit measures written here, or NULL */
  long follow;            /* TressFX followers per guide; -1: default */
  long control;           /* trajectory control points */
  long threads;           /* 0: all cores */
  double voxel;           /* VDB voxel size; 0: from the clusters */
  double follow_radius;   /* < 0: the guides' mean root spacing */
  double tip_separation;
  /* > 0: the width (a diameter, in the input's units) of every strand whose
   * file gives none; 0: a hair fibre's, SATF_IMPORT_FIBRE_WIDTH of the
   * hair's bounding-box diagonal */
  double strand_width;
  double macro_tol; /* 0: no macro-clusters */
  uint64_t seed;
  int quiet; /* no progress bars */
  /* bytes the import may take (SATF_IMPORT_BYTES_PER_POINT a point);
   * <= 0: SATF_IMPORT_DEFAULT_BUDGET */
  double memory_budget;
  /* inputs[0] is a per-frame pattern (one %d) of frames first..last, each
   * re-fitted onto the clusters of the first as keyframes at fps (0: 24) */
  int sequence;
  long first, last;
  double fps;
  /* the hair's fibre, written into the scene's material with the meanings
   * of Cycles' Principled Hair (melanin mode): each < 0 keeps the scene's
   * default (samples/README.md) */
  double melanin, redness, roughness, radial_roughness;
  int shading; /* satf_material_model, or -1: the scene's default */
} satf_import_options;

/* The command line's defaults: control 8, follow -1, follow_radius -1,
 * tip_separation 0.5, macro_tol 0.05, seed 1, memory_budget
 * SATF_IMPORT_DEFAULT_BUDGET, the material's fields and shading -1 (the
 * scene's defaults), the rest 0. */
satf_import_options satf_import_options_default(void);

/* Whether importing `points` strand points fits o's memory budget; if
 * not, an error "WHAT: N strand points would need about X to import ...,
 * over the memory budget of Y: ...". Checked before follow strands are
 * made (naming the count that fits) and after the inputs are read, before
 * anything grows with them. */
satf_status satf_import_check_budget(const satf_import_options *o,
                                     const char *what, size_t points,
                                     satf_error *err);

/* Reads one strand file by its signature ("HAIR" or a .hair name: cyHair;
 * otherwise TressFX, with o's follow strands added). */
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

/* What an import did, for its summary. */
typedef struct satf_import_result {
  int n_strands;
  size_t n_points;
  int n_clusters;
  float rms; /* k-means RMS */
  int n_macro;
  size_t bytes_separate, bytes_shared;
  size_t points, inside;     /* strand points, and inside their envelope */
  satf_import_fit_stats fit; /* the fit report (import_report.c) */
  double distance_sum;       /* of points to their trajectory */
  double width_sum;          /* of the clusters' strand widths */
  int gradient;              /* clusters of layout "gradient" */
  float voxel;
  double vdb_mass;
  /* what the strands were multiplied by to fit the scene limits (1: not
   * rescaled; satf_import_run) */
  double scale;
  /* strands without thickness: the width given them (a hair fibre's, or
   * --strand-width), p10 / p50 / p90 over the strands (0 when the files
   * give a thickness) */
  float spacing_width[3];
  int strand_width_given; /* 1: they are --strand-width's */
  /* TressFX inputs: follow strands grown per guide (the first such file's)
   * and the guides they grew from; follow -1 when no input is TressFX */
  int follow, guides;
  /* 1 when --mesh was given and no strand root lies in or near the
   * transformed mesh's bounds (the head is probably misplaced) */
  int mesh_apart;
  /* the side files as published (satf_import_stage_side), "" when none */
  char vdb_file[4096], strands_file[4096];
  /* seconds from the start to the end of each step, and peak memory */
  double t_read, t_cluster, t_fit, t_vdb0, t_vdb, t_end, peak_mb;
} satf_import_result;

/* The whole import of o: read, cluster, fit, macro-clusters, density grid,
 * the scene (with keys for a sequence), written to o->output. Progress
 * bars go to stderr unless o->quiet. On failure err says what went wrong,
 * as satf-import prints it after "satf-import: ". */
satf_status satf_import_run(const satf_import_options *o,
                            satf_import_result *result, satf_error *err);

/* The summary satf-import prints after an import: "PROG: OUTPUT", then the
 * strands, clusters, macro-clusters, fit quality, density, VDB and times. */
void satf_import_print_summary(FILE *out, const char *prog,
                               const satf_import_options *o,
                               const satf_import_result *r);

#ifdef __cplusplus
}
#endif
#endif
