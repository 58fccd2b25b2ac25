/* render.h - the online renderer (online/render/): frames with named
 * channels written as EXR and PNG, the renderer that turns a scene and a
 * database into pixels (maps, shading, compositing, shadows), and batch
 * frame sequences. */
#ifndef SATF_RENDER_H
#define SATF_RENDER_H

#include "satf/common.h"
#include "satf/db.h"
#include <signal.h>

#include "satf/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Images: the renderer's frame in memory and on disk: a float image
 * of named planar channels ("R", "G", "B", "A" for the beauty pass, plus
 * AOVs named LAYER.CHANNEL with standard channel tokens: "diffuse.R", or
 * "shadow.Y" for a single-channel layer, so Blender, Nuke and OpenImageIO
 * list every layer), written as
 * OpenEXR (through the EXR writer of satf/common.h) or as an 8-bit sRGB PNG for
 * viewing.
 *
 * Row order: every plane is stored TOP row first (image convention, as
 * EXR and PNG store them). GL reads back bottom row first; convert with
 * satf_image_store_interleaved(..., SATF_ROWS_BOTTOM_UP, ...).
 *
 * Colour is linear and, where an alpha channel exists, premultiplied by
 * alpha (what "over" blending in the renderer produces and what EXR
 * expects). */

#define SATF_IMAGE_MAX_CHANNELS 64
#define SATF_IMAGE_MAX_SIDE 32768
#define SATF_IMAGE_MAX_NAME 255

typedef struct satf_image satf_image;

typedef enum satf_row_order {
  SATF_ROWS_TOP_DOWN, /* first row in memory is the top of the picture */
  SATF_ROWS_BOTTOM_UP /* first row is the bottom (glReadPixels) */
} satf_row_order;

/* Creates a width x height image with nchannels channels named names[i]
 * (copied; non-empty, unique, at most SATF_IMAGE_MAX_NAME bytes), all
 * pixels zero. */
satf_status satf_image_create(int width, int height, const char *const *names,
                              int nchannels, satf_image **out, satf_error *err);
void satf_image_destroy(satf_image *img);

int satf_image_width(const satf_image *img);
int satf_image_height(const satf_image *img);
int satf_image_channel_count(const satf_image *img);
const char *satf_image_channel_name(const satf_image *img, int channel);
/* Index of the channel called name, or -1. */
int satf_image_channel_index(const satf_image *img, const char *name);
/* width * height floats, top row first; NULL for a bad index. */
float *satf_image_plane(satf_image *img, int channel);
const float *satf_image_const_plane(const satf_image *img, int channel);

/* Scatters interleaved pixels (src_channels floats per pixel, width x
 * height pixels, rows in `order`) into channels: component k goes to the
 * channel named names[k], or is skipped when names[k] is NULL. An unknown
 * name is an error and nothing is written. */
satf_status satf_image_store_interleaved(satf_image *img, const float *src,
                                         int src_channels,
                                         const char *const *names,
                                         satf_row_order order, satf_error *err);

/* The view layer of an EXR with AOVs: its channels are written as
 * satf.Combined.R/G/B/A, satf.Depth.Z, satf.diffuse.R, ... (LAYER.PASS.
 * CHANNEL, what Blender's compositor and Nuke read as one named layer);
 * an image without AOVs is written as R G B A (Z) unchanged. */
#define SATF_IMAGE_VIEW_LAYER "satf"

/* The camera the image was seen from, row-major column-vector matrices
 * (p' = M p): world to camera (the camera looking down -Z) and world to
 * OpenGL normalised device coordinates (clip space, before the divide).
 * The EXR writers store them as the standard worldToCamera and worldToNDC
 * attributes. satf_image_camera returns 0 (leaving them) when unset. */
void satf_image_set_camera(satf_image *img, const float world_to_camera[16],
                           const float world_to_ndc[16]);
int satf_image_camera(const satf_image *img, float world_to_camera[16],
                      float world_to_ndc[16]);

/* Writes every channel as HALF with ZIP compression. */
satf_status satf_image_write_exr(const satf_image *img, const char *path,
                                 satf_error *err);
/* Writes every channel as 32-bit FLOAT with ZIP compression (for AOVs like
 * depth that half precision would ruin). */
satf_status satf_image_write_exr_float(const satf_image *img, const char *path,
                                       satf_error *err);

/* Writes channels R, G, B (and A if present) as an 8-bit sRGB PNG: RGBA
 * when the image has A, RGB otherwise. Alpha is kept: colour is divided by
 * alpha (PNG stores straight alpha) before the sRGB transfer function;
 * alpha itself is stored linearly, as PNG requires. Values are clamped to
 * [0, 1]; NaN becomes 0. Written through a temporary file renamed into
 * place. */
satf_status satf_image_write_png(const satf_image *img, const char *path,
                                 satf_error *err);
/* Same for one layer: "LAYER.R", "LAYER.G", "LAYER.B" (+ "LAYER.A"), or a
 * single channel "LAYER.Y" (e.g. "shadow.Y") or named LAYER, written as
 * 8-bit grey. */
satf_status satf_image_write_png_layer(const satf_image *img, const char *layer,
                                       const char *path, satf_error *err);
/* Writes the composite (premultiplied R, G, B over the image's background
 * colour, see satf_image_set_background) as an opaque sRGB PNG: the
 * preview of a rendered frame. */
satf_status satf_image_write_png_rgb(const satf_image *img, const char *path,
                                     satf_error *err);
/* The colour behind the image's premultiplied R, G, B (alpha "A"): what
 * satf_image_write_png_rgb and satf_image_flatten composite them over.
 * Black unless set; the renderer sets the scene's background. */
void satf_image_set_background(satf_image *img, const float rgb[3]);
void satf_image_background(const satf_image *img, float rgb[3]);
/* Composites R, G, B over the background in place (RGB += (1 - A) bg; A
 * stays) and makes the background black, so the preview is unchanged:
 * satf-render --background-in-exr. No-op without R, G, B and A. */
void satf_image_flatten(satf_image *img);
/* Decodes the whole PNG at path (so a truncated file fails) and gives its
 * size; for checking that a frame's preview is complete. */
satf_status satf_image_png_size(const char *path, int *width, int *height,
                                satf_error *err);

/* The renderer: the online phase of SATF (paper sec. 6) on OpenGL 4.3+:
 * per frame, database look-ups build each shell layer's re/alpha/s-maps
 * (online/render/maps.h), layers are lit with Kajiya-Kay diffuse and two
 * shifted highlights, shadowed by the s-maps (eq. 12) and a deep opacity map
 * from the key light, and composited order-independently (eq. 14) through
 * per-pixel fragment lists. The caller owns the GL context (headless EGL or
 * a GLFW window) and keeps it current. */

typedef struct satf_renderer satf_renderer;

typedef enum satf_aov {
  SATF_AOV_BEAUTY = 0,
  SATF_AOV_DIFFUSE,
  SATF_AOV_SPEC_I,
  SATF_AOV_SPEC_II,
  SATF_AOV_SHADOW,
  SATF_AOV_ALPHA,
  /* distance along the camera's view axis (Blender's and Nuke's Z) of
   * where the pixel's hair and meshes, front to back, first reach half
   * coverage; the target holds it as two halves (satf_renderer_render_image
   * decodes it into "Z", 1e10 where nothing is that opaque) */
  SATF_AOV_DEPTH,
  SATF_AOV_COUNT
} satf_aov;

const char *satf_aov_name(satf_aov aov);

/* How layers are composited (SATF eq. 14 over every cluster):
 * EXACT sorts every fragment of every pixel by depth (per-pixel fragment
 * arrays); ORDERED draws clusters far to near and, within a cluster, the
 * back halves of the shells outer to inner and then the front halves inner
 * to outer, with fixed-function blending: exact for clusters that do not
 * interleave in depth, and several times faster on a CPU rasteriser. */
typedef enum satf_composite {
  SATF_COMPOSITE_EXACT = 0,
  SATF_COMPOSITE_ORDERED
} satf_composite;

/* Per-frame stage times in ms, named as the paper's Table 1. */
typedef struct satf_frame_timing {
  double index_ms;    /* I: SATF parameters (azimuths, eq. 6 test) */
  double maps_ms;     /* C: look-ups and re/alpha/s-map construction */
  double upload_ms;   /* M: texture mapping (upload of the maps) */
  double lighting_ms; /* L: lighting, shading and compositing (GPU) */
  double shadow_ms;   /* S: deep opacity map passes (GPU) */
  double total_ms;
  long lookups;
  long fragments; /* fragments stored in the per-pixel lists */
  /* L's passes of the exact composite, while satf_renderer_set_pass_timing
   * is on (else 0): the clusters' shells, the strands drawn among them
   * (clusters drawn as their strands) and the sorted resolve */
  double shells_ms, strands_ms, resolve_ms;
} satf_frame_timing;

#define SATF_LOD_LEVELS 4

typedef struct satf_render_stats {
  /* strands: the hair's own (satf_scene_strand_count: procedural clusters'
   * strands and tracks clusters' member strands) */
  long clusters, layers, strands, hsvs, macro_clusters, prototypes_shared;
  /* pixels of the last frame that received more fragments than the
   * per-pixel arrays hold (64; exact compositing): they keep the nearest */
  long overflow_pixels;
  /* the last frame's level of detail (satf_renderer_set_lod): clusters per
   * level (0: every shell layer read; n: every 2^n-th, faded towards
   * 2^(n+1); the last bin counts n and up), those drawn as one layer, and
   * those drawn with a coarser proxy */
  long lod_levels[SATF_LOD_LEVELS];
  long lod_single, lod_coarse;
} satf_render_stats;

/* Where the maps (SATF sec. 6.2; the physical mode's, maps of every
 * light's fibre lobes) are built when the eye or a light moves: CPU, the
 * database looked up on the CPU and the maps uploaded (the reference);
 * GPU, a compute pass writing them into their textures from the
 * database's records kept on the GPU (no look-up on the CPU and no
 * upload). The same maps up to half-float rounding. AUTO, the default,
 * takes the GPU's on a hardware GPU and the CPU's on a software
 * rasteriser (satf_gl_renderer_is_software): on llvmpipe (2 threads) the
 * compute pass takes 3-10 times the CPU's look-ups and upload (640x480,
 * an orbit: cluster_6a 57 against 6 ms, hair_7c 239 against 86, the
 * imported ponytail 642 against 84), and 4-9 times in the physical mode
 * (cluster_6a 170 against 18 ms, hair_7a 281 against 42, the ponytail
 * 1132 against 314; a loaded machine); on an NVIDIA H200 it takes 0.1-10
 * ms where the look-ups and upload take 7-107 (docs/performance.md). */
typedef enum satf_maps_mode {
  SATF_MAPS_CPU = 0,
  SATF_MAPS_GPU,
  SATF_MAPS_AUTO
} satf_maps_mode;
#define SATF_MAPS_DEFAULT SATF_MAPS_AUTO

/* The renderer's memory for a scene, in bytes, by what grows with it;
 * estimated from the scene and its database alone, before anything is
 * built, so that a render over a budget can be refused before it starts.
 * On llvmpipe what the GPU keeps is the process's memory too. */
typedef struct satf_render_memory {
  double hsvs;    /* features, neighbours, maps and textures of every HSV */
  double strands; /* procedural and track strands */
  double pixels;  /* exact compositing's fragment arrays, frame targets */
  double vdb;     /* VDB density grids, each file once */
  /* the database's records; the physical shading's copy of them
   * re-levelled at the hair's absorption, and its M_p table */
  double database;
  /* SATF_MAPS_GPU: the records, tables and every geometry's sectors and
   * neighbours the GPU's maps keep and their compute programs, less the
   * CPU's copy of the maps that they never fill; 0 with the CPU's maps */
  double gpu_maps;
  /* the source strands drawn instead of the clusters
   * (satf_renderer_set_strands, satf-render --strands): their ribbons and
   * light per point, and the strand pass's programs and buffers where no
   * cluster is drawn as its strands already; 0 without them */
  double strand_path;
  double fixed; /* GL driver, shaders, the program */
  double total;
} satf_render_memory;

/* What the estimate takes beyond the scene. Start from
 * satf_render_memory_options_default() and change what differs: a
 * zeroed struct means sparse_strands 0, every cluster drawn as shells. */
typedef struct satf_render_memory_options {
  long width, height; /* the image */
  /* the database the renderer is made with (for the physical shading the
   * fibre one); NULL: neither it nor the GPU's maps are counted (a lower
   * bound, for a refusal before the database is read) */
  const satf_db *db;
  /* satf_renderer_set_maps; SATF_MAPS_AUTO is counted as the CPU's maps:
   * what it is on a software rasteriser, and on a hardware GPU the GPU's
   * maps live in the GPU's own memory */
  satf_maps_mode maps;
  /* satf_renderer_set_sparse_strands' setting: which clusters are drawn as
   * their strands, with no maps (0: none) */
  int sparse_strands;
  /* the points of the source strands satf_renderer_set_strands draws
   * instead of the clusters (0: none) */
  size_t strand_points;
} satf_render_memory_options;

/* 640x480, no database, SATF_MAPS_DEFAULT (counted as the CPU's maps),
 * SATF_SPARSE_STRANDS_DEFAULT, the clusters drawn: the renderer's own
 * defaults, to change what differs. */
satf_render_memory_options satf_render_memory_options_default(void);

/* Fills *parts (when not NULL) and returns parts->total. */
double satf_render_memory_estimate(const satf_scene *scene,
                                   const satf_render_memory_options *opt,
                                   satf_render_memory *parts);
/* "HSVs", "strands", "pixels", "VDB density", "the database", "the GPU's
 * maps" or "the strand path": the largest part that the scene or the
 * options change. */
const char *satf_render_memory_largest(const satf_render_memory *m);

/* Builds clusters, shells, meshes, density features and GL resources.
 * `threads` = 0 uses all cores. */
satf_status satf_renderer_create(const satf_scene *scene, const satf_db *db,
                                 int width, int height, int threads,
                                 satf_renderer **out, satf_error *err);
/* The same, calling progress(ctx, clusters built, clusters) as the set-up
 * goes (a large imported scene takes seconds); progress may be NULL. */
satf_status satf_renderer_create_progress(const satf_scene *scene,
                                          const satf_db *db, int width,
                                          int height, int threads,
                                          satf_progress_fn progress,
                                          void *progress_ctx,
                                          satf_renderer **out, satf_error *err);
void satf_renderer_destroy(satf_renderer *r);

satf_status satf_renderer_resize(satf_renderer *r, int width, int height,
                                 satf_error *err);
void satf_renderer_stats(const satf_renderer *r, satf_render_stats *stats);
void satf_renderer_size(const satf_renderer *r, int *width, int *height);

/* Mutable state for interactive use; start as in the scene. */
satf_scene_camera *satf_renderer_camera(satf_renderer *r);
satf_scene_effects *satf_renderer_effects(satf_renderer *r);
satf_scene_light *satf_renderer_light(satf_renderer *r, int index);
int satf_renderer_light_count(const satf_renderer *r);
void satf_renderer_set_composite(satf_renderer *r, satf_composite mode);
/* Anti-aliasing: each frame drawn `samples` times (clamped to [1,
 * SATF_SCENE_MAX_SAMPLES]) with the camera jittered inside the pixel and
 * averaged; starts as the scene's image.samples. */
void satf_renderer_set_samples(satf_renderer *r, int samples);
int satf_renderer_samples(const satf_renderer *r);
satf_composite satf_renderer_composite(const satf_renderer *r);
/* The film's pixel filter across the strands drawn as strands (the strand
 * path and the sparse clusters): a one-pixel box, or the Blackman-Harris
 * filter Cycles' film uses by default (1.5 pixels by Blender's setting, 3
 * pixels of support), whose faint fringe on hair thinner than a pixel
 * matches a path tracer's frame, at about twice the strands' fragments.
 * AUTO (a renderer's default) takes Blackman-Harris for hair of at most
 * SATF_RENDER_FILTER_AUTO_STRANDS strands (the strands set's, else the
 * scene's clusters'), whose doubled fragments cost little (sparse strands:
 * Bangs_100's 100), and the box for denser hair. */
typedef enum satf_pixel_filter {
  SATF_PIXEL_FILTER_BOX = 0,
  SATF_PIXEL_FILTER_BLACKMAN_HARRIS,
  SATF_PIXEL_FILTER_AUTO
} satf_pixel_filter;
#define SATF_RENDER_FILTER_AUTO_STRANDS 1000
void satf_renderer_set_pixel_filter(satf_renderer *r, satf_pixel_filter f);
satf_pixel_filter satf_renderer_pixel_filter(const satf_renderer *r);
/* Sparse clusters drawn as their strands: a cluster whose density is its
 * own strands' tracks (satf-import's "tracks") and holds at most
 * max_strands of them, or is a tuft of short strands
 * (satf_scene_tracks_as_strands), is drawn as those strands, ribbons of
 * the width its density assumes, composited with the clusters (0: every
 * cluster is drawn as a cluster). A handful of strands fills no volume for
 * SATF's shells to stand for, and the shells spread short strands over
 * the cluster's length; drawn as strands they look like themselves. */
#define SATF_SPARSE_STRANDS_DEFAULT SATF_SCENE_SPARSE_STRANDS
#define SATF_SPARSE_STRANDS_MAX 1024
satf_status satf_renderer_set_sparse_strands(satf_renderer *r, int max_strands,
                                             satf_error *err);
int satf_renderer_sparse_strands(const satf_renderer *r);
/* Level of detail by size on screen (off at creation: every cluster at
 * full detail): a cluster a few pixels wide reads fewer shell layers,
 * each standing for the ones it skips, faded continuously with its width
 * (no popping), and draws a coarser proxy. */
void satf_renderer_set_lod(satf_renderer *r, int on);
int satf_renderer_lod(const satf_renderer *r);
/* Times L's passes apart (satf_frame_timing: shells_ms, strands_ms,
 * resolve_ms; off at creation): the GPU is waited for between them, which
 * a frame otherwise does not do, so L may take a little longer with it. */
void satf_renderer_set_pass_timing(satf_renderer *r, int on);
int satf_renderer_pass_timing(const satf_renderer *r);
/* The cluster shadows' deep opacity map is kept across scene changes
 * (satf_renderer_set_scene: animated hair) while no cluster's control
 * point has moved more than `texels` of its texels across the light or
 * of its slabs along it (1 at creation); negative: drawn again after
 * every scene change, whatever moved. */
void satf_renderer_set_shadow_move(satf_renderer *r, float texels);
float satf_renderer_shadow_move(const satf_renderer *r);

/* Where the maps are built: satf_maps_mode (above). */
/* Switches (every instance's maps are built again at the next frame);
 * fails, keeping the mode, where the GPU's program or tables cannot be
 * made. SATF_MAPS_AUTO (a new renderer's mode) resolves against the
 * current context's GL_RENDERER; its GPU's maps are made at the first
 * frame that builds maps, and where they cannot be made or built the
 * frame and those after it take the CPU's. satf_renderer_maps returns the
 * mode resolved (CPU or GPU), satf_renderer_maps_note why auto fell back
 * to the CPU's ("" where it did not). */
satf_status satf_renderer_set_maps(satf_renderer *r, satf_maps_mode mode,
                                   satf_error *err);
satf_maps_mode satf_renderer_maps(const satf_renderer *r);
const char *satf_renderer_maps_note(const satf_renderer *r);
/* "cpu", "gpu" or "auto"; satf_maps_mode_parse returns -1 for anything
 * else. */
const char *satf_maps_mode_name(satf_maps_mode mode);
int satf_maps_mode_parse(const char *name, satf_maps_mode *mode);

/* Renders one frame of `aov` into the renderer's RGBA16F target. */
satf_status satf_renderer_render(satf_renderer *r, satf_aov aov,
                                 satf_frame_timing *timing, satf_error *err);
/* The target's colour texture (linear RGB, A = hair coverage). */
unsigned satf_renderer_texture(const satf_renderer *r);
unsigned satf_renderer_framebuffer(const satf_renderer *r);

/* Renders the beauty pass (and with aovs != 0 every AOV) into a new image
 * with channels R G B A (colour premultiplied over transparent black, as
 * compositors expect of an EXR; A the coverage; the scene's background is
 * the image's background colour, see satf_image_set_background) and, for
 * AOVs, diffuse.R/G/B, specI.R/G/B, specII.R/G/B, shadow.Y, alpha.Y (all
 * premultiplied over black) and Z (SATF_AOV_DEPTH; with several samples
 * a pixel takes their median, never their mean: a mean across an edge is
 * a depth where nothing is). */
satf_status satf_renderer_render_image(satf_renderer *r, int aovs,
                                       satf_image **out,
                                       satf_frame_timing *timing,
                                       satf_error *err);

/* Switches to another state of the same scene (an animation frame): same
 * macro-clusters, instance counts and shells. Only prototypes whose
 * geometry changed are rebuilt (their density features are kept: density
 * lives in the cluster's own frame), only moved instances re-placed; camera
 * and lights are taken from `scene`, which must outlive its use. *rebuilt
 * (may be NULL) is the number of prototypes rebuilt. */
satf_status satf_renderer_set_scene(satf_renderer *r, const satf_scene *scene,
                                    int *rebuilt, satf_error *err);

/* The strand reference path: with strands set, frames draw these strands
 * (world space) instead of the clusters, as anti-aliased camera-facing
 * ribbons of their own width (a strand thinner than a pixel is drawn a
 * pixel wide with its coverage as alpha), lit by the same lights,
 * material and shading model (SATF eq. 9-11), shadowed by a deep opacity
 * map built from the strands, over the same opaque meshes: the image the
 * clusters approximate. Segments are sorted far to near each frame, so it
 * is slow next to the clusters. Strand i has counts[i] >= 2 points, taken
 * in order from xyz (3 floats each); thickness (a diameter per point, in
 * scene units) may be NULL, and then every point is default_width wide.
 * n_strands = 0 goes back to the clusters. The strands stay through
 * satf_renderer_set_scene. */
satf_status satf_renderer_set_strands(satf_renderer *r, int n_strands,
                                      const int *counts, const float *xyz,
                                      const float *thickness,
                                      float default_width, satf_error *err);
/* Strands drawn instead of the clusters (0: the cluster path). */
int satf_renderer_strand_count(const satf_renderer *r);

/* Writes every shell layer mesh of every prototype (OpenMesh, by the
 * extension of `path`: .obj or .ply) as PATH-m<macro>-l<layer>.EXT; sets
 * *written to the number of files. */
satf_status satf_renderer_export_meshes(const satf_renderer *r,
                                        const char *path, int *written,
                                        satf_error *err);

/* Draws the target to the bound framebuffer (viewport already set),
 * converting linear to sRGB. */
void satf_renderer_present(satf_renderer *r);

/* Sequences: batch rendering of a range of animation frames to OpenEXR
 * (SATF Fig. 8): one snapshot per frame (satf/scene.h) switched into the
 * renderer so only what moves is rebuilt, each frame written through a
 * temporary file so a killed batch never leaves a partial frame, resuming
 * by skipping frames already on disk, and a contact sheet of thumbnails. */

typedef struct satf_sequence_opts {
  int first, last;           /* inclusive frame range */
  const char *exr_pattern;   /* printf pattern with one integer, e.g.
                                out/frame_%04d.exr; may be NULL */
  const char *png_pattern;   /* the same for PNG previews; may be NULL */
  const char *contact_sheet; /* PNG of all frames' thumbnails; may be NULL */
  int resume;                /* skip frames whose every output is complete */
  int aovs;
  int quiet;
  int background_in_exr; /* frames' R, G, B flattened over the background
                            (satf_image_flatten) before the EXR is written */
  /* when non-NULL and set (by a signal handler), the batch stops before
   * its next frame: satf_sequence_stats.interrupted, and SATF_OK */
  const volatile sig_atomic_t *stop;
} satf_sequence_opts;

typedef struct satf_sequence_stats {
  int rendered, skipped;
  int interrupted; /* 1: opts.stop ended the batch before its last frame */
  double seconds;
  satf_frame_timing mean; /* over rendered frames */
} satf_sequence_stats;

/* Checks that a pattern holds exactly one integer conversion (%d, %04d,
 * %5d ...) and no other %. */
satf_status satf_sequence_check_pattern(const char *pattern, satf_error *err);

/* Renders the range with `r`, which was created from `scene` (the
 * animated scene, outliving the call). */
satf_status satf_sequence_render(satf_renderer *r, const satf_scene *scene,
                                 const satf_sequence_opts *opts,
                                 satf_sequence_stats *stats, satf_error *err);

#ifdef __cplusplus
}
#endif
#endif
