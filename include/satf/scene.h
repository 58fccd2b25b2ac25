/* scene.h - the scene file: a JSON description of a hair volume in the SATF
 * four-level hierarchy (Xu et al. 2006, sec. 3.1): hair volume ->
 * macro-clusters (one prototype cluster plus per-instance transforms) ->
 * clusters (generalized disks, sec. 3.2) -> hair density (sec. 3.3), plus
 * the material (sec. 6.3-6.4), effect switches, camera, lights, background
 * and the HRIR database to render it with, optionally animated by
 * keyframes (the animation API at the end of this header).
 *
 * samples/README.md is the format reference (every key, type, unit, default
 * and allowed range). This header owns the in-memory data model: a
 * satf_scene is a plain tree of structs, allocated by satf_scene_load /
 * satf_scene_parse and freed as a whole by satf_scene_destroy. Every field
 * has been validated and defaulted when the load succeeds; callers read the
 * fields directly and must not modify or free them. A program that builds a
 * scene (the importer) starts from satf_scene_create, fills the fields with
 * malloc'ed arrays and strings that satf_scene_destroy will free, and
 * writes it with satf_scene_write: the one writer of the format.
 *
 * Inside the library (online/scene/README.md) the reader is a chain
 * without cycles: report (key paths, messages) -> values (typed JSON reads)
 * -> tracks (the one "keys" reader) -> parse_instance -> parse_cluster ->
 * parse -> load; snapshots use only check (validation), interp and the
 * keyframe data (anim); write reads the data model and uses check's
 * normalization, equal reads the data model only. */
#ifndef SATF_SCENE_H
#define SATF_SCENE_H

#include <stddef.h>
#include <stdint.h>

#include "satf/satf.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Limits enforced by validation (documented in samples/README.md). */
#define SATF_SCENE_MAX_LAYERS 256
#define SATF_SCENE_MAX_ST 4096
#define SATF_SCENE_MIN_SU 3
#define SATF_SCENE_MAX_SU 4096
#define SATF_SCENE_MAX_CORE 0.95
#define SATF_SCENE_MAX_HSV 50000000ull     /* over the whole scene */
#define SATF_SCENE_MAX_CONTROL_POINTS 4096 /* per curve */
#define SATF_SCENE_MAX_MACRO_CLUSTERS 65536
#define SATF_SCENE_MAX_INSTANCES 65536       /* per macro-cluster */
#define SATF_SCENE_MAX_CLUSTERS 1000000      /* instances over the scene */
#define SATF_SCENE_MAX_LIGHTS 8              /* what the renderer draws */
#define SATF_SCENE_MAX_STRANDS 10000000      /* per cluster */
#define SATF_SCENE_MAX_TRACK_SLICES 256      /* tracks density: t slices */
#define SATF_SCENE_MAX_TRACK_POINTS 50000000 /* tracks density: per cluster */
/* A cluster of at most this many strands is drawn as its strands (the
 * renderer's default, satf_renderer_set_sparse_strands) and fitted one
 * strand to a cluster (satf-import) */
#define SATF_SCENE_SPARSE_STRANDS 8
/* A track's strand end ("ends") closer to its first or last slice than
 * this many slice intervals adds no point: the slice holds it. satf-import
 * writes ends only where one lies farther out; the renderer draws the
 * same test. */
#define SATF_SCENE_TRACK_END_MARGIN 0.1f
#define SATF_SCENE_MAX_CLUMPS 16   /* clumps or holes per cluster */
#define SATF_SCENE_MAX_COORD 1e6   /* |coordinate| in scene units */
#define SATF_SCENE_MAX_IMAGE 16384 /* pixels per side */
#define SATF_SCENE_MAX_SAMPLES 64  /* anti-aliasing samples per pixel */
#define SATF_SCENE_MAX_FILE_BYTES (64u << 20)
#define SATF_SCENE_MAX_FRAME 10000000 /* |frame| in the animation range */
#define SATF_SCENE_MAX_FPS 1000.0
#define SATF_SCENE_MAX_KEYS 65536         /* per animated object */
#define SATF_SCENE_MAX_KEYS_TOTAL 1000000 /* over the scene */

/* A 1-D B-spline given by its control values (SATF eq. 2: A(t), B(t),
 * theta(t)); a constant has count == 1. All curves of the scene are clamped
 * uniform B-splines of degree min(3, count - 1) on t in [0, 1]. */
typedef struct satf_scene_curve {
  int count;
  float *values;
} satf_scene_curve;

/* The sampling of a cluster's shell into HSVs (SATF eq. 3): `layers`
 * shells between the core radius (a fraction `core` of the envelope) and the
 * envelope, st steps along t and su sectors around u. */
typedef struct satf_scene_shell {
  int layers;
  int st;
  int su;
  float core;
} satf_scene_shell;

typedef enum satf_scene_density_type {
  SATF_SCENE_DENSITY_PROCEDURAL = 0,
  SATF_SCENE_DENSITY_VDB,
  SATF_SCENE_DENSITY_TRACKS /* the cluster's own strands, as tracks */
} satf_scene_density_type;

typedef enum satf_scene_layout {
  SATF_SCENE_LAYOUT_UNIFORM = 0,
  SATF_SCENE_LAYOUT_CLUMPED,
  SATF_SCENE_LAYOUT_GRADIENT,
  SATF_SCENE_LAYOUT_HOLES,
  SATF_SCENE_LAYOUT_COUNT
} satf_scene_layout;

/* The bottom level of the hierarchy (SATF sec. 3.3): either strands placed
 * procedurally in the cluster's cross-section, or a density grid read from
 * an OpenVDB file. */
typedef struct satf_scene_density {
  satf_scene_density_type type;
  /* procedural */
  int strands;   /* strands in the cluster */
  uint64_t seed; /* placement seed, < 2^53 */
  satf_scene_layout layout;
  float strand_width; /* strand diameter, in units of the cluster radius */
  float scale;        /* multiplies the density field */
  int clumps;         /* clumped: number of clumps */
  float clump_spread; /* clumped: clump std. deviation / cluster radius */
  int holes;          /* holes: number of empty discs */
  float hole_radius;  /* holes: hole radius / cluster radius */
  float gradient;     /* gradient: density slope from core to surface */
  /* procedural and tracks: the angle (degrees, 0 to 90) at which the
   * fibres cross the trajectory, curling about it (0: along it); the
   * physical shading averages the lobes' M_p over that cone of tangents */
  float curl;
  /* vdb */
  char *vdb_file; /* resolved against the scene file's directory */
  char *vdb_grid; /* grid name, default "density" */
  /* tracks (with strand_width and scale): where each of the cluster's own
   * strands passes, in the normalised cross-section (x, y) = v (cos u,
   * sin u), at track_slices evenly spaced t (slice i at t = i / (slices -
   * 1)). Track k holds slices track_first[k] .. track_first[k] +
   * track_count[k] - 1 (a strand runs from its root to its tip, so it may
   * start after t = 0 and end before t = 1); its (x, y) pairs follow the
   * previous track's in track_xy. track_ends (NULL when absent: the
   * tracks' first and last slices are the strands' ends) holds 6 per
   * track, (t, x, y) of its strand's two ends, the lower t first: a strand
   * starts and stops between slices, and drawn as a strand (the renderer's
   * sparse clusters) it reaches its true root and tip. track_width (NULL
   * when absent: every strand is strand_width wide) holds one per track,
   * its strand's own diameter in units of the cluster radius, as
   * strand_width; the renderer draws the strands of a sparse cluster at
   * these widths (strand_width stays their mean, what the density uses). */
  int track_slices, n_tracks;
  int *track_first, *track_count;
  float *track_xy;
  float *track_ends;
  float *track_width;
} satf_scene_density;

/* One generalized-disk cluster (SATF eq. 1-2): an ellipse with half-axes
 * a(t), b(t) and twist phase theta(t) swept along the trajectory T(t). */
typedef struct satf_scene_cluster {
  int n_points;           /* trajectory control points (>= 2) */
  float *trajectory;      /* 3 * n_points, x y z interleaved */
  satf_scene_curve a;     /* half major axis, scene units, > 0 */
  satf_scene_curve b;     /* half minor axis, scene units, > 0 */
  satf_scene_curve twist; /* radians */
  satf_scene_shell shell;
  satf_scene_density density;
} satf_scene_cluster;

/* Maps the prototype's space to the world: p_world = M * (p, 1), M stored
 * row-major (m[3], m[7], m[11] are the translation). Affine, non-singular. */
typedef struct satf_scene_instance {
  float m[16];
} satf_scene_instance;

/* Second level of the hierarchy (SATF sec. 3.1): clusters whose geometries
 * are transforms of one prototype. */
typedef struct satf_scene_macro_cluster {
  char *name; /* optional, NULL when absent */
  satf_scene_cluster prototype;
  int n_instances; /* >= 1 */
  satf_scene_instance *instances;
} satf_scene_macro_cluster;

/* Which shading the hair gets: the paper's Kajiya-Kay lighting of the
 * maps (SATF eq. 9-11) or the physically based fibre model (d'Eon 2011,
 * Chiang 2016; satf/fiber.h) with the fibre database's per-lobe records. */
typedef enum satf_material_model {
  SATF_MATERIAL_KK = 0,
  SATF_MATERIAL_PHYSICAL,
  SATF_MATERIAL_MODEL_COUNT
} satf_material_model;

/* Shading parameters (SATF eq. 9-12, Scheuermann 2004), and the fibre of
 * the physical model with the meanings of Blender Cycles' Principled Hair
 * BSDF (melanin mode) and pbrt-v4's HairBxDF. */
typedef struct satf_scene_material {
  satf_material_model model;
  float melanin, redness; /* [0, 1]: melanin amount and its pheomelanin share */
  float roughness;        /* longitudinal roughness beta_m, [0, 1] */
  float radial_roughness; /* azimuthal roughness beta_n, [0, 1] */
  float cuticle_tilt;     /* alpha, degrees (Cycles' "Offset") */
  float ior;              /* eta of the fibre */
  int has_absorption;     /* absorption below replaces the melanin */
  float absorption[3];    /* sigma_a per unit fibre radius, RGB */
  float k_dif, k_speI, k_speII;  /* eq. 9, 10, 11 coefficients */
  float exponent_I, exponent_II; /* Phong exponents k_h of eq. 10 and 11 */
  float shift_I;                 /* eq. 10: t~ = normalize(t + shift_I n) */
  float shift_II;                /* eq. 11: t~ = normalize(t - shift_II n) */
  float f_dif[3], f_speI[3], f_speII[3]; /* RGB colours */
  float k_shadow;                        /* eq. 12 self-shadow intensity */
  float noise; /* secondary-highlight noise strength */
} satf_scene_material;

typedef struct satf_scene_effects {
  int satf; /* 0: plain shifted Kajiya-Kay (Scheuermann) */
  int secondary_highlight;
  int self_shadow;     /* eq. 12 s-maps */
  int cluster_shadows; /* shadows between clusters (deep opacity maps) */
} satf_scene_effects;

typedef struct satf_scene_camera {
  float position[3];
  float target[3];
  float up[3];     /* normalized, not parallel to target - position */
  float fov_y;     /* degrees, [0.1, 179] */
  float near_clip; /* 0 with far_clip 0: renderer picks from bounds */
  float far_clip;
  int automatic; /* 1 when position/target were framed from bounds */
} satf_scene_camera;

typedef enum satf_scene_light_type {
  SATF_SCENE_LIGHT_DIRECTIONAL = 0,
  SATF_SCENE_LIGHT_POINT
} satf_scene_light_type;

typedef struct satf_scene_light {
  satf_scene_light_type type;
  float direction[3]; /* directional: unit direction the light travels */
  float position[3];  /* point */
  float color[3];
  float intensity;
} satf_scene_light;

/* An opaque mesh (a head, a body): OBJ or PLY read with OpenMesh, drawn
 * with Lambert shading, occluding hair and casting shadows into the deep
 * opacity map. */
typedef struct satf_scene_mesh {
  char *file;     /* resolved against the scene file's directory */
  float color[3]; /* diffuse albedo, linear RGB */
  float m[16];    /* row-major transform to world */
} satf_scene_mesh;

#define SATF_SCENE_MAX_MESHES 64

typedef struct satf_scene_image {
  int width, height;
  int samples; /* jittered samples per pixel, [1, SATF_SCENE_MAX_SAMPLES] */
} satf_scene_image;

/* Keyframes of an animated scene: opaque, read through the functions below. */
typedef struct satf_scene_animation satf_scene_animation;

typedef struct satf_scene {
  char *name;           /* the name used in messages (the path, if loaded) */
  char *description;    /* optional, NULL when absent */
  int n_macro_clusters; /* >= 1 */
  satf_scene_macro_cluster *macro_clusters;
  satf_scene_material material;
  satf_scene_effects effects;
  satf_scene_camera camera;
  int n_lights; /* >= 1 (a default key light when absent) */
  satf_scene_light *lights;
  float background[3];
  char *database; /* resolved path, NULL when absent */
  /* The scene's strands as a cyHair .hair file (the importer writes them in
   * scene coordinates beside the scene): resolved against the scene file's
   * directory, NULL when absent. */
  char *strands_file;
  int n_meshes; /* opaque meshes, 0 when absent */
  satf_scene_mesh *meshes;
  satf_scene_image image;
  /* Warnings (unknown keys); read them with satf_scene_warning*. */
  int n_warnings;
  char **warnings;
  /* NULL for a static scene and for a snapshot (satf_scene_at_frame); the
   * fields above then hold the static values, the defaults of every key. */
  satf_scene_animation *animation;
} satf_scene;

/* Reads and validates a scene file. Relative paths inside it resolve
 * against the directory of `path`. On failure *out is NULL and err names
 * the file, the key path and what is wrong. */
satf_status satf_scene_load(const char *path, satf_scene **out,
                            satf_error *err);

/* Validates len bytes of JSON (no terminator needed). name_for_messages
 * prefixes every message and its directory part (if any) is the base of
 * relative paths; NULL means "<scene>" and no base. */
satf_status satf_scene_parse(const char *json, size_t len,
                             const char *name_for_messages, satf_scene **out,
                             satf_error *err);

void satf_scene_destroy(satf_scene *scene);

/* A scene named `name` with no macro-clusters and every other value at the
 * default a file would get: material, effects, an automatic camera, one
 * key light, background and image size. The caller adds macro-clusters
 * (and may replace any field) before using or writing it. */
satf_status satf_scene_create(const char *name, satf_scene **out,
                              satf_error *err);

/* Appends an opaque mesh `file` (copied; the path the scene should hold)
 * with the default colour and the identity transform. */
satf_status satf_scene_add_mesh(satf_scene *scene, const char *file,
                                satf_error *err);

/* m = T(translate) R(axis, angle_rad) S(scale), row-major, exactly as the
 * parser composes an instance's or a mesh's "transform" (axis unit). */
void satf_scene_matrix_trs(const double translate[3], const double axis[3],
                           double angle_rad, const double scale[3],
                           float m[16]);

/* Normalizes v as the parser normalizes light directions and up vectors;
 * returns 0 (v unchanged) when v has no length. */
int satf_scene_normalize(float v[3]);

/* The scene as JSON text (malloc'ed, NUL-terminated) in the format of
 * samples/README.md, every value written so that satf_scene_parse gives
 * the same scene back (satf_scene_equal) and writing that gives the same
 * text. Paths under base_dir (the directory the text will be read from;
 * NULL: none) are written relative to it, others as held. */
satf_status satf_scene_to_json(const satf_scene *scene, const char *base_dir,
                               char **json, satf_error *err);

/* satf_scene_to_json into path, through a temporary file renamed into
 * place. Every path is written relative to path's directory (with "../"
 * steps when the file lies elsewhere; the directories canonical, a file's
 * own name kept), so a folder holding the scene and its files can move as
 * a whole; a path that shares no directory below the root with it (e.g.
 * /usr/share/...) or whose directory does not exist is written absolute.
 * Loading the file finds the same files. */
satf_status satf_scene_write(const satf_scene *scene, const char *path,
                             satf_error *err);

/* Equality of everything a scene file says (not the name or warnings):
 * every field, every key. Bitwise on the floats. */
int satf_scene_equal(const satf_scene *a, const satf_scene *b);

/* Non-fatal findings (unknown keys), each "NAME: key.path: message". */
int satf_scene_warning_count(const satf_scene *scene);
const char *satf_scene_warning(const satf_scene *scene, int index);

/* Replaces the database path (e.g. from the command line; used as given). */
satf_status satf_scene_set_database(satf_scene *scene, const char *path,
                                    satf_error *err);

/* Totals over every instance of every macro-cluster, as in SATF Table 1:
 * clusters (C#), layers (L#), HSVs (H#), procedural strands (S#; VDB
 * clusters count 0). */
uint64_t satf_scene_cluster_count(const satf_scene *scene);
uint64_t satf_scene_layer_count(const satf_scene *scene);
uint64_t satf_scene_hsv_count(const satf_scene *scene);
uint64_t satf_scene_strand_count(const satf_scene *scene);

/* The strand diameter, in scene units, the clusters' procedural density
 * assumes: its strand_width in units of the cluster radius sqrt(mean a *
 * mean b) (what satf-import estimates from the strands' spacing; world
 * sigma = width * radius / 2), scaled by the instance, the median over the
 * placed clusters; 0 when no cluster has a procedural density. */
float satf_scene_density_strand_width(const satf_scene *scene);

/* Whether the renderer draws a cluster whose density is "tracks" (slices,
 * n_tracks and track_count as in satf_scene_density) as its own strands
 * rather than as shells: when it holds at most max_strands strands (too
 * few to fill the volume the shells stand for), or when it is a tuft of
 * short strands, each crossing on average at most half of its slices
 * (fur: the shells spread strands that start and stop along the cluster
 * as if each ran its whole length). max_strands 0: never. satf-import
 * keeps such clusters out of macro-clusters: an instance drawn with its
 * prototype's strands would draw other strands than its own. */
int satf_scene_tracks_as_strands(int slices, int n_tracks,
                                 const int *track_count, int max_strands);

/* HSVs of one cluster: layers * st * su (SATF eq. 3). */
uint64_t satf_scene_cluster_hsv_count(const satf_scene_cluster *cluster);

/* The points of a "tracks" density's strands (its track_count summed); 0
 * for any other density. */
size_t satf_scene_track_points(const satf_scene_density *density);

/* The control-value count a, b and twist share once constants are repeated
 * (validation ensures each is a single value or has this count). */
int satf_scene_cluster_curve_count(const satf_scene_cluster *cluster);

/* Writes n control values of curve into out: its own when it has n, its
 * constant repeated when it has one (a clamped B-spline whose control values
 * are all equal is that constant). */
void satf_scene_curve_expand(const satf_scene_curve *curve, int n, float *out);

/* p_world = M * (p, 1). out may alias p. */
void satf_scene_instance_apply(const satf_scene_instance *instance,
                               const float p[3], float out[3]);

/* Axis-aligned world bounds of the hair volume: the control-point hull of
 * each trajectory (a B-spline lies inside it) grown by the largest radius,
 * through every instance transform. */
void satf_scene_bounds(const satf_scene *scene, float lo[3], float hi[3]);

const char *satf_scene_layout_name(satf_scene_layout layout);

/* Animation - keyframes of a scene (samples/README.md, "Animation";
 * SATF Fig. 8): the frame range and rate of an animated scene, static
 * snapshots of it at any frame, and cheap comparisons that tell a renderer
 * what changed between two snapshots.
 *
 * An animated scene is an ordinary satf_scene whose fields hold the static
 * values (the defaults of every key) plus keyframes that only this API
 * reads. A snapshot is a complete static satf_scene with every animated
 * value interpolated; render it as any loaded scene and free it with
 * satf_scene_destroy. */

/* Makes a built scene animated over frames [first, last] at fps (both in
 * the limits above); fails when it is animated already. */
satf_status satf_scene_set_animation(satf_scene *scene, double fps, int first,
                                     int last, satf_error *err);

/* Appends a key at `frame` (in the range, after the previous key) to
 * macro_clusters[index].prototype: copies of its trajectory (3 * n_points)
 * and of a, b and twist (each with the static count); NULL keeps the
 * static value. The values are not validated here: loading the written
 * file does that. */
satf_status satf_scene_add_prototype_key(satf_scene *scene, int index,
                                         double frame, const float *trajectory,
                                         const float *a, const float *b,
                                         const float *twist, satf_error *err);

/* 1 when the scene file had an "animation" object (even with no keys). */
int satf_scene_is_animated(const satf_scene *scene);

/* The inclusive frame range; returns satf_scene_is_animated(scene). A
 * static scene gives 0 and 0. */
int satf_scene_frame_range(const satf_scene *scene, int *first, int *last);

/* Frames per second; 0 for a static scene. */
double satf_scene_fps(const satf_scene *scene);

/* A static copy of scene at `frame` (fractional frames interpolate too;
 * frames outside the keys hold the first or last key). Names, paths,
 * material, effects, image and every unanimated value are copied; the
 * snapshot has no warnings and satf_scene_is_animated(*out) == 0. A static
 * scene gives a plain copy. Fails (naming the scene, the object's key path
 * and the frame) on a non-finite frame or when interpolation produces an
 * unusable value: a trajectory whose points all coincide, a singular
 * instance transform, a camera looking along its up vector or at its own
 * position, or a zero light direction. */
satf_status satf_scene_at_frame(const satf_scene *scene, double frame,
                                satf_scene **out, satf_error *err);

/* 1 when macro_clusters[index].prototype has keys (its geometry may differ
 * between snapshots); 0 otherwise or for a bad index. */
int satf_scene_prototype_is_animated(const satf_scene *scene, int index);

/* 1 when instance j of macro_clusters[index] has keys. */
int satf_scene_instance_is_animated(const satf_scene *scene, int index,
                                    int instance);

/* Equality of what a renderer builds from: the cluster geometry
 * (trajectory, a, b, twist, shell and density parameters), the instance
 * transforms of a macro-cluster, the camera, one light. Bitwise on the
 * floats, so two snapshots taken where nothing moves compare equal. */
int satf_scene_prototype_equal(const satf_scene_cluster *a,
                               const satf_scene_cluster *b);
int satf_scene_instances_equal(const satf_scene_macro_cluster *a,
                               const satf_scene_macro_cluster *b);
int satf_scene_camera_equal(const satf_scene_camera *a,
                            const satf_scene_camera *b);
int satf_scene_light_equal(const satf_scene_light *a,
                           const satf_scene_light *b);

#ifdef __cplusplus
}
#endif
#endif
