/* strands.h - hair given as strands (polylines), the way artists and
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
#ifndef SATF_STRANDS_H
#define SATF_STRANDS_H

#include <stddef.h>
#include <stdint.h>

#include "satf/satf.h"

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

/* Mean distance between each strand's root and the nearest other root: the
 * scale of a sensible follow radius. 0 for fewer than two strands. */
float satf_strand_set_root_spacing(const satf_strand_set *s);

#ifdef __cplusplus
}
#endif
#endif
