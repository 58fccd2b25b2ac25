/* import.h - strand hair into satf scenes (online/import/): strand sets and
 * the strand files' readers and writers, and the whole import
 * (satf_import_run) that satf-import runs. Its stages (clustering,
 * fitting, refinement, the fit report, density, macro-clusters, the scene
 * and its publication) are the library's own: online/import/
 * import_internal.h, which the library and its tests include.
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
/* the largest coordinate magnitude satf-import takes from a file */
#define SATF_IMPORT_MAX_INPUT_COORD 1e15

typedef struct satf_strand_set satf_strand_set;

/* Copies n_strands strands: strand i has counts[i] points (>= 2), taken in
 * order from points (3 floats each). thickness (one per point) may be NULL.
 * Rejects non-finite values and absurd counts. */
satf_status satf_strand_set_create(int n_strands, const int *counts,
                                   const float *points, const float *thickness,
                                   satf_strand_set **out, satf_error *err);
void satf_strand_set_destroy(satf_strand_set *s);

/* A new set holding the strands of a followed by those of b (for importing
 * several files into one scene). Thickness and colour are kept only when
 * both have them. */
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
/* Colours of the points of strand i (r g b a point, as the file gave
 * them), or NULL when the set has none. */
const float *satf_strand_set_colour(const satf_strand_set *s, int i);
/* Gives every point of s a colour: 3 floats a point in the set's point
 * order, copied (replacing any it had); every value finite. */
satf_status satf_strand_set_add_colour(satf_strand_set *s, const float *rgb,
                                       satf_error *err);
/* Axis-aligned bounds of every point. */
void satf_strand_set_bounds(const satf_strand_set *s, float lo[3], float hi[3]);
/* Polyline length of strand i. */
float satf_strand_set_length(const satf_strand_set *s, int i);

/* ---- cyHair .hair ------------------------------------------------------ */

satf_status satf_hair_parse(const void *data, size_t size, const char *name,
                            satf_strand_set **out, satf_error *err);
satf_status satf_hair_read(const char *path, satf_strand_set **out,
                           satf_error *err);
/* Writes segments, points and (when the set has them) thickness and colour
 * arrays,
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
 * strand element (`strand`, `strands`, `hair` or `curve`, or any other
 * element with such a property) with each strand's point count (property
 * `vertex_count`, `vertices`, `num_vertices`, `nverts`, `num_points`,
 * `points` or `count`) or segment count (`segments`, `num_segments`,
 * `segment_count`, `nsegs`, `num_segs`), the strands' points in vertex
 * order; or, where no element holds counts, an `edge` element (`vertex1`,
 * `vertex2`) chained into polylines, each from its lower-numbered end. ascii,
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

/* ---- Wavefront OBJ polylines (strands_obj.c) ---------------------------- */

/* `v x y z` vertices (a weight after them is dropped; an r g b colour
 * after them, on every vertex, is kept as the points' colours; OBJ holds
 * no width) and `l` polylines of 1-based or negative indices (`i/t`
 * allowed), their segments chained into strands as PLY edges are (each
 * from its lower-numbered end); faces and everything else are skipped, so
 * a groom exported with its head reads as its hair. */
satf_status satf_obj_parse(const void *data, size_t size, const char *name,
                           satf_strand_set **out, satf_error *err);
satf_status satf_obj_read(const char *path, satf_strand_set **out,
                          satf_error *err);

/* ---- Which format a strand file is (strands_detect.c) ------------------- */

typedef enum satf_strands_format {
  SATF_STRANDS_UNKNOWN,
  SATF_STRANDS_HAIR, /* "HAIR" */
  SATF_STRANDS_TFX,  /* a TressFX version 1..6 in the first float */
  SATF_STRANDS_PLY,  /* "ply" line */
  SATF_STRANDS_USC,  /* strand and point counts that fill the file exactly */
  SATF_STRANDS_OBJ   /* text whose first statement is an OBJ one */
} satf_strands_format;

/* The format the bytes say, or UNKNOWN. */
satf_strands_format satf_strands_detect(const void *data, size_t size);
/* The format a file name's extension names (.hair .tfx .ply .data .obj). */
satf_strands_format satf_strands_format_of_name(const char *path);
/* "cyHair", "TressFX", "PLY", "USC-HairSalon .data", "OBJ" or "unknown". */
const char *satf_strands_format_name(satf_strands_format f);

/* ---- The whole import (import_run.c, import_sequence.c) ---------------- */

/* The user's knob: how closely clusters follow their strands. */
typedef enum satf_import_quality {
  SATF_IMPORT_QUALITY_DEFAULT = 0, /* what zeroed options mean */
  SATF_IMPORT_QUALITY_DRAFT,
  SATF_IMPORT_QUALITY_HIGH
} satf_import_quality;

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
  /* over the clusters drawn as shells: p50, p90, max of their strands' p90
   * angle to the trajectory (degrees), and the strands of those whose p90
   * exceeds SATF_IMPORT_ACROSS_DEGREES */
  float direction[3];
  long long across_strands;
} satf_import_fit_stats;

/* A shell cluster whose strands' p90 angle to its trajectory exceeds this
 * (degrees) is counted in satf_import_fit_stats.across_strands: its shells
 * shade the hair along the trajectory, across many of its strands. */
#define SATF_IMPORT_ACROSS_DEGREES 30.0f

#define SATF_IMPORT_MAX_INPUTS 64
/* clusters an import may make (--clusters) */
#define SATF_IMPORT_MAX_CLUSTERS 8192

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
  /* 1: the inputs (strands and mesh) are Z-up, as Blender's: turned to the
   * scene's Y-up by (x, y, z) -> (x, z, -y) before the transforms below */
  int up_z;
  /* where the hair goes (after up_z), as mesh_* for the mesh */
  double hair_translate[3], hair_axis[3], hair_angle_deg, hair_scale[3];
} satf_import_options;

/* The command line's defaults: control 8, follow -1, follow_radius -1,
 * tip_separation 0.5, macro_tol 0.05, seed 1, memory_budget
 * SATF_IMPORT_DEFAULT_BUDGET, the material's fields and shading -1 (the
 * scene's defaults), the rest 0. */
satf_import_options satf_import_options_default(void);

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
  /* strands dropped because all their points coincide (no length), and
   * points merged into an equal one before them */
  int dropped_strands;
  size_t merged_points;
  /* the side files as published (satf_import_stage_side), "" when none */
  char vdb_file[4096], strands_file[4096];
  /* seconds from the start to the end of each step, and peak memory */
  double t_read, t_cluster, t_fit, t_vdb0, t_vdb, t_end, peak_mb;
  /* seconds from the start to the end of the macro-clusters and of the
   * scene's check, and the peak memory (MB) at the end of reading,
   * clustering and the scene's check: where a slow or large import spends */
  double t_macro, t_check, mb_read, mb_cluster, mb_check;
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
