/* renderer_internal.h - the renderer's state and what its files offer each
 * other (private to online/render). A frame runs as stages, each in its
 * own file owning its own state:
 *   renderer.c   the public API; chooses a drawing path once a frame and
 *                runs it once per anti-aliasing sample (samples.c)
 *   hierarchy.c  the prototypes and instances (SATF's macro-clusters)
 *   resources.c  the GL programs, output target and meshes
 * the drawing paths (path.h), each calling none of the others:
 *   clusters.c   SATF's clusters: cluster_cpu.c (look-ups, maps: Table 1
 *                I, C, M), cluster_dom.c (their shadows: S), cluster_gpu.c
 *                (shading and compositing: L), sparse.c (clusters of few
 *                strands drawn as those strands)
 *   strands.c    the source strands, the reference the clusters approximate
 *   baseline.c   Scheuermann 2004's textured patches (SATF Fig. 4a)
 * and under them, calling no path:
 *   view.c       camera, lights, bounds, jitter     (view.h)
 *   dom.c        the deep opacity map               (dom.h)
 *   lists.c      the per-pixel fragment arrays      (lists.h)
 *   draw.c       the frame's start, shading uniforms (draw.h)
 *   depth.c      the depth AOV from the fragment arrays (depth.h)
 *   ribbons.c    strands on the GPU as ribbons, for strands.c and sparse.c
 * Names here carry the owning file's name instead of the public satf_
 * prefix. */
#ifndef SATF_RENDERER_INTERNAL_H
#define SATF_RENDERER_INTERNAL_H

#include "dom.h"
#include "fiber_gpu.h"
#include "lists.h"
#include "lod.h"
#include "maps.h"
#include "maps_fiber.h"
#include "samples.h"
#include "satf/density.h"
#include "satf/geometry.h"
#include "satf/gl.h"
#include "satf/render.h"
#include "view.h"

struct render_path;

/* A macro-cluster's prototype: its generalized cylinder, shell geometry,
 * density and drawn proxy. */
typedef struct proto {
  satf_cluster *cluster;
  satf_shell_geom geom; /* features: procedural density, shared */
  satf_strands *strands;
  satf_vdb_grid *vdb;
  int layers;
  GLuint proxy_vao; /* the drawn outer shell (hierarchy.c) */
  GLuint proxy_vbo, proxy_ibo;
  /* its proxies (lod.h): index ranges, and the bounding sphere, widest
   * section and two-row bands' sag lod.c measures */
  GLsizei lod_first[LOD_PROXIES], lod_count[LOD_PROXIES];
  float lod_sphere[4], lod_width, lod_sag;
  /* its instances: r->insts[first_inst .. first_inst + ninsts), whose maps
   * lie in the renderer's shared texture arrays (r->map_arrays; one draw
   * call covers a run of them: cluster_gpu.c) */
  int first_inst, ninsts;
  int textured; /* its instances have their layers in r->map_arrays */
  int sparse;   /* drawn as its strands (sparse.c), not as a cluster */
  /* its density, features, neighbours, instance texels and map textures
   * are built (hierarchy.c: only for prototypes drawn as clusters) */
  int ready;
  /* its density is its strands' (tracks, VDB: imported hair), so its
   * records take an orientation-free level (satf_map_options) */
  int from_strands;
  float tilt; /* the density's curl: its fibres' angle to the trajectory,
                 radians */
} proto;

/* One placed copy of a prototype with its own maps. */
typedef struct inst {
  int proto;
  float m[16], inv[16], nmat[9];
  float centre[3]; /* world position of the cluster's middle, for sorting */
  satf_shell_geom geom; /* shallow copy; own features only with a VDB */
  int own_features;
  satf_neighbor_cache *own_neighbors; /* with own (VDB) features */
  float *angles;
  /* its maps (maps.h layout, one texture layer per shell, r->quads RGBA
   * halfs a texel) as half floats (half.h), what its texture holds */
  uint16_t *texels;
  float eye[3], light[4];
  GLuint tex; /* the shared texture array holding its maps (r->map_arrays) */
  int layer0; /* its first layer there */
  /* what the next frame's maps must look up again (cluster_cpu.c): angles of
   * the last look-ups, and whether the texels are new since the last upload */
  float *looked_up;
  int stale_upload;
  int still;    /* this frame's azimuths are all those of the last look-ups */
  int replaced; /* moved or reshaped since its azimuths were computed */
  int mirrored; /* negative determinant: front faces wind clockwise */
  /* sparse (its prototype's): its strands' segments in r->sparse */
  size_t seg0, nsegs;
  float lod; /* this frame's level and proxy (lod_frame.c) */
  int lod_proxy;
} inst;

/* The strand reference path's strands and programs (strands.c). */
typedef struct strands_gpu strands_gpu;

/* An opaque scene mesh on the GPU. */
typedef struct mesh_gpu {
  GLuint vao, vbo, ibo;
  GLsizei count;
  float m[16], nmat[9], color[3];
} mesh_gpu;

struct satf_renderer {
  const satf_scene *scene;
  const satf_db *db;
  view view; /* camera, lights, bounds, image size, jitter (view.h) */
  satf_scene_effects effects;
  int threads;
  satf_render_stats stats;
  /* the drawing path of the last frame (path.h; renderer.c chooses it, a
   * path's create makes its state idempotently) */
  const struct render_path *path;
  /* the hierarchy (hierarchy.c): prototypes and their instances */
  int nprotos, ninsts;
  proto *protos;
  inst *insts;
  /* the instances' map textures: texture arrays shared by every prototype
   * of one map size, and the instances in the order of their arrays, which
   * the shading passes draw them in (hierarchy.c: map_textures_create) */
  GLuint *map_arrays;
  int n_map_arrays;
  int *tex_order;
  int map_binds; /* map textures the last shading pass bound (cluster_gpu.c) */
  /* the database's maps (maps.h) and their width; the physical mode's maps
   * (maps_fiber.h), NULL in the paper's mode, and the RGBA half quads of a
   * map texel: 2 with them (key and fill, one GL_RGBA32UI texel), else 1
   * (GL_RGBA16F) */
  satf_maps *maps;
  satf_map_options map_opt;
  int w;
  satf_maps_fiber *fiber;
  int quads;
  fiber_gpu *fgpu; /* its fibre's uniforms and tables (with fiber) */
  /* the lights the physical maps were last made for (cluster_cpu.c):
   * while they and an instance's eye stay, its maps stay */
  satf_scene_light fiber_lights[SATF_SCENE_MAX_LIGHTS];
  int fiber_nlights, fiber_trt; /* and the TRT switch (Fig. 4b) */
  /* per map thread, one instance's maps in floats (cluster_cpu.c builds
   * them there, then packs them to halfs): scratch_n buffers of
   * scratch_floats */
  float **scratch;
  int scratch_n;
  size_t scratch_floats;
  int maps_changed; /* instances whose maps the last frame changed */
  /* where the paper's maps are built (satf_renderer_set_maps): the CPU
   * (cluster_cpu.c) or the GPU (maps_gpu.h: mgpu, made when set, or for
   * SATF_MAPS_AUTO at the first frame that builds maps); maps_auto: the
   * mode was auto's choice, which falls back to the CPU's where the GPU's
   * fail (maps_note: why, "" otherwise) */
  satf_maps_mode maps_mode;
  struct maps_gpu *mgpu;
  int maps_auto;
  char maps_note[sizeof(((satf_error *)0)->message)];
  int incremental; /* 0: every HSV looked up every frame (the reference) */
  /* the clusters' drawing (cluster_gpu.c): compositing mode, programs (with
   * the level of detail compiled in: *_lod), and per instance, for
   * instanced draws, the model matrices and the eye and lights in each
   * prototype frame (cluster_cpu_instance_data) */
  satf_composite composite;
  satf_pixel_filter pixel_filter; /* strand_cover.glsl */
  GLuint prog_shade, prog_shade_ordered, prog_depth, prog_dom, prog_resolve;
  GLuint prog_resolve_depth; /* SATF_AOV_DEPTH's resolve (depth.c) */
  GLuint prog_resolve_pool;  /* the resolve reading the lists' pool */
  GLuint prog_shade_lod, prog_shade_ordered_lod;
  GLuint inst_models, inst_shading;
  int instanced; /* 0: one draw per instance (a test's reference) */
  int lod;       /* level of detail by size on screen (lod.c) */
  /* satf_renderer_set_pass_timing, and this frame's L by pass so far:
   * shells, strands among them, resolve (cluster_gpu.c) */
  int pass_timing;
  double pass_ms[3];
  lod_params lod_opt;
  /* sparse clusters' strands (sparse.c), NULL if none; sparse_max: the
   * most strands a cluster drawn so may hold (0: none is) */
  strands_gpu *sparse;
  int sparse_sorted; /* its segments far to near (sparse_composite) */
  int sparse_max;
  /* the strand path's strands (strands.c); NULL: no strands given */
  strands_gpu *strands;
  struct baseline *baseline; /* the baseline path's state (baseline.c) */
  /* under the paths (resources.c): the output, the meshes and their
   * programs, the display blit, an empty vertex array */
  satf_gl_target *out;
  int nmeshes;
  mesh_gpu *meshes;
  GLuint prog_mesh, prog_mesh_depth, prog_mesh_dom, prog_display, empty_vao;
  dom_map dom; /* the key light's deep opacity map (dom.c) */
  /* the fill light's, drawn and read in the physical mode where the scene
   * has two lights or more (draw_fill_shadows): its targets exist there */
  dom_map fill_dom;
  frag_lists lists; /* the per-pixel fragment arrays (lists.c) */
  /* anti-aliasing: samples per pixel and their accumulator (samples.c) */
  int samples;
  sample_accum accum;
};

/* The scene's name for messages. */
static inline const char *scene_name(const satf_scene *scene) {
  return scene->name ? scene->name : "scene";
}

/* ---- hierarchy.c: prototypes and instances ---------------------------- */

/* The scene gives A, B and twist as separate curves; the cluster takes one
 * control polygon for the three, so shorter ones are resampled linearly
 * to n values. */
void hierarchy_resample_curve(const satf_scene_curve *c, int n, float *out);
/* The generalized cylinder of a scene cluster, its A, B and twist resampled
 * to one control count (what the renderer draws; tools that place points
 * as the renderer does build it the same way). */
satf_status hierarchy_cluster_create(const satf_scene_cluster *c,
                                     satf_cluster **out, satf_error *err);
/* Builds every prototype and instance of r->scene; a prototype drawn as
 * its strands (hierarchy_sparse at r->sparse_max) gets its geometry only,
 * not the density, features, neighbours and maps of a drawn cluster. */
satf_status hierarchy_build(satf_renderer *r, satf_progress_fn progress,
                            void *progress_ctx, satf_error *err);
/* Whether a scene cluster of "tracks" density holds 1 .. max strands and
 * is drawn as them (sparse.c) rather than as a cluster. */
int hierarchy_sparse(const satf_scene_cluster *c, int max);
/* Rows of an instance's map texture for st HSVs along the cluster: two an
 * HSV (maps.h) */
int hierarchy_map_rows(int st);
/* Gives every prototype now drawn as a cluster (proto.sparse 0) what
 * hierarchy_build left out for those drawn as strands: after
 * satf_renderer_set_sparse_strands lowers the threshold. */
satf_status hierarchy_prepare(satf_renderer *r, satf_error *err);
/* Whether `scene` has r's hierarchy (macro-clusters, instance counts,
 * shells): only geometry and transforms may change between frames. */
satf_status hierarchy_check(const satf_renderer *r, const satf_scene *scene,
                            satf_error *err);
/* Switches to `scene` (see satf_renderer_set_scene; hierarchy_check has
 * passed): rebuilds changed prototypes, re-places moved instances and adds
 * the rebuilt prototypes to *moved. */
satf_status hierarchy_update(satf_renderer *r, const satf_scene *scene,
                             int *moved, satf_error *err);
void hierarchy_release(satf_renderer *r);
/* The clusters' density strand diameter (strand_width x radius, their
 * mean over the procedural densities); 0 if none says. */
float hierarchy_density_width(const satf_renderer *r);
/* The diameter of the hair the deep opacity map counts for the clusters
 * (and the baseline's patches): the sparse clusters' strands' median
 * width, else hierarchy_density_width. */
float hierarchy_hair_width(const satf_renderer *r);
/* The same hair cut into finer clusters is the same hair: the light
 * falls off through it over the same depth, but the mean shell radius
 * shrinks with the clusters and took the slabs with it. The shared
 * ponytail imported at --tolerance 1.5% and 1.25% with its narrow
 * clusters kept as shells (SATF_IMPORT_SHELL_STRAND_WIDTH at 0.16: 558
 * and 733 shell clusters, mean radius 2.05 and 1.66 against the
 * default's 3.13 in 242) came out at luminance 0.77 and 0.89 of Cycles'
 * where the default comes to 0.91. So the scale is at least this share
 * of the hair's bounding radius: the default imports' smallest ratio (the
 * ponytail's 0.0296; a straight curtain's 0.035, Table 1's samples
 * 0.044-0.18), so their frames stay as they were. */
#define SHELL_RADIUS_FLOOR 0.029f
/* The mean root radius of the clusters drawn with shells (not as their
 * strands, hierarchy_sparse), at least SHELL_RADIUS_FLOOR of the hair's
 * bounding radius, which sets the deep opacity map's slab (dom_place);
 * all clusters' when every one is drawn as its strands. *shells (may be
 * NULL): how many are drawn with shells. */
float hierarchy_shell_radius(const satf_renderer *r, int *shells);
/* Instance indices far to near from `eye` (malloc'd; NULL: no memory);
 * equal distances by position, never by list order. */
int *hierarchy_far_to_near(const satf_renderer *r, const float eye[3]);

/* ---- resources.c: GL resources under the paths ------------------------ */

/* Meshes (grown into the view's bounds), programs, the output target, the
 * fragment arrays, the deep opacity map and the instance buffers; r's
 * hierarchy is already built. */
satf_status resources_build(satf_renderer *r, satf_error *err);
/* The output target and fragment arrays for the view's image size. */
satf_status resources_alloc_screen(satf_renderer *r, satf_error *err);
void resources_release(satf_renderer *r);

/* ---- cluster_cpu.c: the clusters' CPU work (Table 1: I, C, M) --------- */

/* Sector angles, layer maps and s-map sums of every instance, uploaded;
 * with r->incremental only the HSVs whose azimuths changed are looked up
 * again, and only changed instances uploaded (r->maps_changed counts
 * them). */
satf_status cluster_cpu_update_maps(satf_renderer *r, satf_frame_timing *t,
                                    satf_error *err);
/* Marks every HSV of `in` for a look-up at the next frame (its geometry,
 * features or transform changed). */
void cluster_cpu_forget_lookups(inst *in);
/* cluster_cpu_forget_lookups of every instance that has looked up. */
void cluster_cpu_forget_all_lookups(satf_renderer *r);
/* Makes r take `mode` as SATF_MAPS_AUTO's choice (renderer.c: for tests,
 * as on another context). */
void renderer_maps_auto_as(satf_renderer *r, satf_maps_mode mode);
/* Frees the map threads' scratch buffers. */
void cluster_cpu_release(satf_renderer *r);
/* The per-instance data of the instanced draws (r->inst_models,
 * r->inst_shading: glsl/cluster_vs.glsl, glsl/shade_fs.glsl) for the
 * current camera, lights and transforms. */
satf_status cluster_cpu_instance_data(satf_renderer *r, satf_error *err);
/* std430 layout of glsl/shade_fs.glsl's per-instance view: the eye (xyz,
 * w the level of detail) and SATF_SCENE_MAX_LIGHTS lights, 4 floats each
 * (the bytes of one instance's view in r->inst_shading). */
#define CLUSTER_VIEW_FLOATS (4 + 4 * SATF_SCENE_MAX_LIGHTS)

/* ---- lod_frame.c: level of detail per frame (rules: lod.h) ------------ */

/* Instance i's widest section and its two-row bands' sag, in pixels on
 * screen for r's camera, at the nearest point of its bounding sphere
 * (1e30 with the eye inside it). */
void lod_screen_size(const satf_renderer *r, int i, float *width_px,
                     float *sag_px);
/* Each instance's level and proxy for the current camera (every level 0
 * and the full proxy while r->lod is off), and the frame's LOD mix in
 * r->stats. */
void lod_update(satf_renderer *r);

/* ---- cluster_dom.c: the clusters' shadows (Table 1: S) ---------------- */

/* The deep opacity map of the clusters (and the sparse clusters' strands),
 * drawn again unless the one drawn last still stands for this frame. */
void cluster_dom_update(satf_renderer *r);
/* The largest move, in texels across the light or slabs along it, of any
 * cluster control point (or radius) since the map was drawn; INFINITY when
 * it cannot be measured (no map, or other clusters). */
float cluster_dom_hair_move(const satf_renderer *r);

/* ---- cluster_gpu.c: the clusters' shading (Table 1: L) ---------------- */

/* The outermost shells of every cluster drawn as a cluster with `prog`:
 * their depth or their alpha into the deep opacity map's bound target
 * (coarse: the light passes' proxy), else their shading; returns the map
 * textures it bound. */
int cluster_gpu_draw(const satf_renderer *r, GLuint prog,
                     const float viewproj[16], int coarse);
/* The frame begun (meshes) and the per-pixel fragment arrays filled;
 * returns the largest number of fragments a pixel received and sets
 * *overflow to the pixels that received more than r->lists.slots. Without
 * `nearest` each pixel keeps the first slots fragments to arrive. `nearest`
 * (the depth keys allocated) follows a call without it for the same frame: the
 * pixels that received more than slots there are filled again with their
 * slots nearest fragments, whatever their arrival order; the others keep
 * theirs (and the counts, so the figures are that call's). */
GLuint cluster_gpu_lists(satf_renderer *r, satf_aov aov,
                         const float viewproj[16], int nearest, long *fragments,
                         long *overflow);
/* The arrays of the last cluster_gpu_lists sorted and composited (SATF
 * eq. 14) over the frame it began, or their depth (depth.c): once a
 * frame, after the arrays' last fill (a pass drawn again, grown or
 * nearest, replaces what it would have composited); pool: the plain
 * pass's pool holds the fragments past the slots (lists_pool_held) and no
 * nearest pass was drawn, so the colour's resolve keeps the nearest of
 * the arrays and the pool. */
void cluster_gpu_resolve(satf_renderer *r, satf_aov aov,
                         const float viewproj[16], int pool);
/* Clusters drawn far to near with "over" blending. */
satf_status cluster_gpu_ordered(satf_renderer *r, satf_aov aov,
                                const float viewproj[16], satf_error *err);

/* ---- strand_curve.c: polylines refined along their curves -------------- */

/* a refined piece's chord strays from the curve by at most
 * STRAND_CURVE_TOLERANCE of the strand's width; a segment is cut into at
 * most STRAND_CURVE_MAX_PIECES pieces */
#define STRAND_CURVE_TOLERANCE 0.5f
#define STRAND_CURVE_MAX_PIECES 16

/* Strands as refined polylines: n strands of counts[i] points, `total` in
 * all, each with its width. */
typedef struct strand_curve {
  int n;
  int *counts;
  float *xyz, *width;
  size_t total;
} strand_curve;

/* The n strands of counts[i] points (xyz; widths thickness, or
 * default_width where it is NULL), checked by the caller, refined along
 * their Catmull-Rom curves into *out (strand_curve_free frees it); a strand
 * that would pass 65,536 points keeps its own. */
satf_status strand_curve_refine(int n, const int *counts, const float *xyz,
                                const float *thickness, float default_width,
                                strand_curve *out, satf_error *err);
void strand_curve_free(strand_curve *c);

/* ---- ribbons.c: strands on the GPU as camera-facing ribbons ----------- */

/* n strands of counts[i] points (xyz), each point's width (thickness, or
 * default_width when thickness is NULL); with `list` also the program that
 * writes into the per-pixel arrays; with `curves` drawn along the curves
 * through their points (strand_curve.c), else as their polylines (whose
 * segments a caller may then address by index). *out is NULL for n = 0. */
satf_status strands_gpu_create(int n, const int *counts, const float *xyz,
                               const float *thickness, float default_width,
                               int list, int curves, strands_gpu **out,
                               satf_error *err);
void strands_gpu_destroy(strands_gpu *s);
int strands_gpu_count(const strands_gpu *s);
/* The ribbons' bounds. */
void strands_gpu_bounds(const strands_gpu *s, float lo[3], float hi[3]);
/* Segments far to near from `eye` (painter's order for the "over" draws). */
void strands_gpu_sort(strands_gpu *s, const float eye[3]);
/* Segments in the order of their strands (strand i's segments follow
 * strand i - 1's), for draws of ranges and for the per-pixel arrays, which
 * need no order. */
void strands_gpu_in_order(strands_gpu *s);
size_t strands_gpu_segments(const strands_gpu *s);
/* The strands' median width (diameter, scene units); 0 for NULL. */
float strands_gpu_width(const strands_gpu *s);
/* The shading program, every fragment (whole or partly covered) blended
 * "over" (list_mode -1) or into the per-pixel arrays in that mode of
 * cluster_gpu_lists, bound with the frame's material, lights and view;
 * in the physical shading list modes -1 and 0 light the strand points
 * (strand_light_cs.glsl), which the nearest modes 1 and 2 read after
 * them. */
void strands_gpu_begin(const satf_renderer *r, strands_gpu *s, satf_aov aov,
                       const float viewproj[16], int list_mode);
void strands_gpu_draw(const strands_gpu *s, size_t first, size_t count);
/* The strands over the bound frame (its meshes drawn), as the strand path
 * composites them: whole fragments depth-tested and written, then the
 * partly covered ones blended in the segments' order (strands_gpu_sort
 * first for painter's order). */
void strands_gpu_composite(const satf_renderer *r, strands_gpu *s, satf_aov aov,
                           const float viewproj[16]);
/* Binds the shading program of strands_gpu_begin again (list_mode -1),
 * its uniforms as that call left them. */
void strands_gpu_use(const strands_gpu *s);
/* Whether any ribbon is at least a pixel wide for viewproj on a frame
 * `height` pixels high. */
int strands_gpu_any_wide(const strands_gpu *s, const float viewproj[16],
                         int height);
/* With the program of strands_gpu_begin bound: only the fragments the
 * strands cover whole (whole 1), only those they cover partly (0), or
 * every one (-1). */
void strands_gpu_whole(const strands_gpu *s, int whole);
/* The depth of the fragments the strands cover whole (opaque: what lies
 * behind them in a pixel is hidden) written into the bound framebuffer's
 * depth; 0 if no strand is a pixel wide (nothing written). */
int strands_gpu_opaque_depth(const satf_renderer *r, const strands_gpu *s,
                             const float viewproj[16]);
/* The strands into the bound deep opacity map (a dom_hair_fn's body). */
void strands_gpu_dom(satf_renderer *r, strands_gpu *s, int opacity);

/* ---- sparse.c: clusters of few strands drawn as those strands -------- */

/* Which prototypes are sparse (their "tracks" density holds 1 ..
 * r->sparse_max strands: proto.sparse) and their instances' strands on the
 * GPU, in world space; called when the hierarchy is built or updated. */
satf_status sparse_build(satf_renderer *r, satf_error *err);
/* The strands a sparse cluster c (density "tracks") is drawn as, built
 * without GL so that tests can measure them: the points of each of its
 * tracks placed on `cluster` (c's generalized cylinder as hierarchy.c
 * builds it) and mapped by the instance transform m, into xyz (3 a point)
 * and width (1 a point), each strand's point count into counts; returns
 * the strands written. sparse_cluster_size gives the room they need. */
int sparse_place(const satf_cluster *cluster, const satf_scene_cluster *c,
                 const float m[16], int *counts, float *xyz, float *width);
void sparse_cluster_size(const satf_scene_density *d, int *strands,
                         size_t *points);
void sparse_release(satf_renderer *r);
/* The sparse strands into the per-pixel arrays (list mode of
 * cluster_gpu_lists) or into the bound deep opacity map. */
void sparse_lists(const satf_renderer *r, satf_aov aov,
                  const float viewproj[16], int mode);
void sparse_dom(satf_renderer *r, int opacity);
/* Before the fragment arrays are filled: the depth of the fragments the
 * sparse strands cover whole (strands_gpu_opaque_depth), so no fragment
 * behind one is stored; whether any was written. */
int sparse_opaque_depth(const satf_renderer *r, const float viewproj[16]);
/* The strands' shading program bound once per ordered frame: its
 * uniforms and textures stay while sparse_ordered switches to it. */
void sparse_ordered_begin(satf_renderer *r, satf_aov aov,
                          const float viewproj[16]);
/* Whether every instance is drawn as its strands (no shells: fur at its
 * default import, Bangs_100). */
int sparse_only(const satf_renderer *r);
/* Then no shell fragment needs sorting against the strands, and they
 * composite as the strand path's do (strands_gpu_composite, segments
 * sorted far to near) over the bound frame, without the per-pixel arrays:
 * 200K fur strands of 4 points at 640x480, L 10.3 s in the arrays against
 * 3.6 s so (kk, llvmpipe). The segments stay sorted until
 * sparse_ordered_begin puts the instances' ranges back. */
void sparse_composite(satf_renderer *r, satf_aov aov, const float viewproj[16]);
/* Instance i's strands blended "over" (cluster_gpu_ordered's order), with
 * the program of sparse_ordered_begin left bound; 0 if it is not sparse
 * (it is drawn as a cluster). */
int sparse_ordered(satf_renderer *r, int i);

/* ---- baseline.c: Scheuermann 2004 (paper 002) ------------------------- */

/* Ambient occlusion of layer k (0 innermost) of `layers` whose texture has
 * mean alpha `mean_alpha`. */
float baseline_layer_occlusion(float mean_alpha, int k, int layers);

#endif
