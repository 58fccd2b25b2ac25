/* renderer_internal.h - the renderer's state and what its files offer each
 * other (private to online/render). The renderer is five files, one job
 * each: renderer.c the public API (create, destroy, scene switches,
 * frames, images), hierarchy.c the prototypes and instances, resources.c
 * the GL programs, targets and meshes, frame.c the per-frame CPU work
 * (look-ups, maps, transforms) and passes.c the GPU passes; strands.c
 * draws the source strands instead (the reference path). Names here
 * carry the owning file's name instead of the public satf_ prefix. */
#ifndef SATF_RENDERER_INTERNAL_H
#define SATF_RENDERER_INTERNAL_H

#include "fiber_gpu.h"
#include "lod.h"
#include "maps.h"
#include "maps_fiber.h"
#include "satf/density.h"
#include "satf/geometry.h"
#include "satf/gl.h"
#include "satf/render.h"

/* Side of the deep opacity map, in texels. */
#define DOM_SIZE 512
/* The most a cluster's control point may move, in texels across the light
 * or slabs along it, before the deep opacity map is drawn again (passes.c;
 * satf_renderer_set_shadow_move). */
#define DOM_MOVE_TOL 1.0f
/* Fragments each pixel can keep at first; the arrays grow (up to
 * SATF_MAX_FRAGMENTS) when a frame needs more. */
#define START_SLOTS 16

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
   * share texture arrays of chunk_insts instances each (one draw call
   * covers a run of them: passes.c) */
  int first_inst, ninsts, chunk_insts, nchunks;
  GLuint *map_tex;
  int sparse; /* drawn as its strands (sparse.c), not as a cluster */
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
  GLuint tex; /* its prototype's texture array holding its maps */
  int layer0; /* its first layer there */
  /* what the next frame's maps must look up again (frame.c): angles of the
   * last look-ups, and whether the texels are new since the last upload */
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
  satf_maps *maps;
  /* the physical mode's maps (maps_fiber.h), NULL in the paper's mode, and
   * the RGBA half quads of a map texel: 2 with them (key and fill, one
   * GL_RGBA32UI texel), else 1 (GL_RGBA16F) */
  satf_maps_fiber *fiber;
  int quads;
  fiber_gpu *fgpu; /* its fibre's uniforms and tables (with fiber) */
  satf_map_options map_opt;
  satf_scene_camera camera;
  satf_scene_effects effects;
  satf_scene_light lights[SATF_SCENE_MAX_LIGHTS];
  /* the lights the physical maps were last made for (frame.c): while
   * they and an instance's eye stay, its maps stay */
  satf_scene_light fiber_lights[SATF_SCENE_MAX_LIGHTS];
  int fiber_nlights, fiber_trt; /* and the TRT switch (Fig. 4b) */
  int nlights;
  int width, height, threads, w;
  float lo[3], hi[3];
  int nprotos, ninsts, nmeshes;
  mesh_gpu *meshes;
  GLuint prog_mesh, prog_mesh_depth, prog_mesh_dom;
  proto *protos;
  inst *insts;
  satf_render_stats stats;
  /* GL */
  satf_composite composite;
  GLuint prog_shade, prog_shade_ordered, prog_depth, prog_dom, prog_resolve,
      prog_display;
  /* the shading programs with the level of detail compiled in (r->lod) */
  GLuint prog_shade_lod, prog_shade_ordered_lod;
  /* per instance, for instanced draws (passes.c): the model matrices and
   * the eye and lights in each prototype frame (frame_instance_data) */
  GLuint inst_models, inst_shading;
  int instanced;   /* 0: one draw per instance (a test's reference) */
  int incremental; /* 0: every HSV looked up every frame (the reference) */
  int lod;         /* level of detail by size on screen (lod.c) */
  lod_params lod_opt;
  int maps_changed; /* instances whose maps the last frame changed */
  /* per map thread, one instance's maps in floats (frame.c builds them
   * there, then packs them to halfs): scratch_n buffers of
   * scratch_floats */
  float **scratch;
  int scratch_n;
  size_t scratch_floats;
  /* the deep opacity map's inputs when it was drawn (reused while the
   * light, the hair and its maps stay: passes.c) */
  int dom_valid;
  float dom_viewproj[16], dom_light_slab;
  long dom_reuses; /* frames that reused it */
  /* the maps' alpha, which the map reads, follows the eye's azimuth: the
   * eye when the map was drawn, whether maps were uploaded since, and how
   * far (radians, seen from any cluster) the eye may turn before the map
   * is drawn again for them (passes.c; INFINITY by default: never for the
   * eye alone, 0: whenever a map changed) */
  float dom_eye[3], dom_eye_tol;
  int dom_maps_stale;
  /* the map kept across scene changes (issue 12 item 4; passes.c) while
   * no cluster's control point has moved more than dom_move_tol texels
   * across the light or slabs along it (dom_points: each one's world xyz
   * and radius when the map was drawn, dom_npoints of them); dom_move_tol
   * < 0: the exact rule (drawn again after every satf_renderer_set_scene) */
  float dom_move_tol;
  float *dom_points;
  int dom_npoints;
  float dom_light[4]; /* the key light's vector when the map was drawn */
  GLuint empty_vao, counts_tex, frags_tex, list_fbo;
  GLuint keys_tex; /* per-pixel depth keys of the nearest `slots` fragments,
                      made when a pixel first overflows (0: none yet) */
  int slots;       /* fragments kept per pixel */
  /* x, y, width, height of the pixels the last plain list pass overflowed
   * (passes_lists: its nearest passes draw only there) */
  int overflow_box[4];
  satf_gl_target *out, *dom_depth, *dom_opacity;
  float light_viewproj[16], dom_slab;
  strands_gpu *strands; /* strand reference mode (strands.c); NULL: clusters */
  /* sparse clusters' strands (sparse.c), NULL if none; sparse_max: the
   * most strands a cluster drawn so may hold (0: none is) */
  strands_gpu *sparse;
  int sparse_max;
  struct baseline *baseline; /* the --no-satf path's state (baseline.c) */
  /* anti-aliasing (samples.c): samples per pixel, this sample's camera
   * offset in pixels, and the accumulator */
  int samples;
  float jitter[2];
  GLuint prog_accum;
  satf_gl_target *accum;
  int accum_size[2];
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
/* Builds every prototype and instance of r->scene. */
satf_status hierarchy_build(satf_renderer *r, satf_progress_fn progress,
                            void *progress_ctx, satf_error *err);
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

/* ---- resources.c: GL programs, targets and meshes --------------------- */

/* Meshes, programs and every target; r's hierarchy is already built. */
satf_status resources_build(satf_renderer *r, satf_error *err);
/* The output target and fragment arrays for r->width x r->height. */
satf_status resources_alloc_screen(satf_renderer *r, satf_error *err);
/* Fragment arrays of `slots` fragments per pixel. */
satf_status resources_alloc_lists(satf_renderer *r, int slots, satf_error *err);
/* r->keys_tex for r->slots keys per pixel, unless it exists. */
satf_status resources_alloc_keys(satf_renderer *r, satf_error *err);
void resources_release(satf_renderer *r);
/* One program, its fragment shader given SATF_MAX_LIGHTS and
 * SATF_MAX_FRAGMENTS (and `extra`) after its #version line. */
satf_status build_program(const char *label, const char *vs, const char *fs,
                          const char *extra, GLuint *out, satf_error *err);

/* ---- samples.c: anti-aliasing by jittered supersampling --------------- */

/* The camera offset, in pixels within [-1/2, 1/2], of sample `index` of
 * `count` (0, 0 when count is 1). */
void samples_offset(int index, int count, float offset[2]);
/* Adds r->out, weighted 1/count, into the accumulator (cleared at 0). */
satf_status samples_add(satf_renderer *r, int index, int count,
                        satf_error *err);
/* The accumulated average back into r->out. */
satf_status samples_finish(satf_renderer *r, satf_error *err);
void samples_release(satf_renderer *r);

/* ---- frame.c: per-frame CPU work (Table 1: I, C, M) ------------------- */

/* A light as seen from a point: xyz + w (0: direction to it, 1: position). */
void frame_light_vector(const satf_scene_light *l, float out[4]);
/* The same in a frame whose inverse transform is inv. */
void frame_light_local(const float inv[16], const satf_scene_light *l,
                       float out[4]);
/* colour x intensity of every light, 3 floats each. */
void frame_light_colors(const satf_renderer *r, float *col);
/* Sector angles, layer maps and s-map sums of every instance, uploaded;
 * with r->incremental only the HSVs whose azimuths changed are looked up
 * again, and only changed instances uploaded (r->maps_changed counts
 * them). */
satf_status frame_update_maps(satf_renderer *r, satf_frame_timing *t,
                              satf_error *err);
/* Marks every HSV of `in` for a look-up at the next frame (its geometry,
 * features or transform changed). */
void frame_forget_lookups(inst *in);
/* Frees the map threads' scratch buffers. */
void frame_release(satf_renderer *r);
/* The per-instance data of the instanced draws (r->inst_models,
 * r->inst_shading: glsl/cluster_vs.glsl, glsl/shade_fs.glsl) for the
 * current camera, lights and transforms. */
satf_status frame_instance_data(satf_renderer *r, satf_error *err);
/* Bytes of one instance's view in r->inst_shading. */
size_t frame_instance_view_bytes(void);
void frame_camera(const satf_renderer *r, float viewproj[16]);
/* The camera's view and projection without the sample's jitter. */
void frame_view_proj(const satf_renderer *r, float view[16], float proj[16]);
/* r->light_viewproj and r->dom_slab for the key light's deep opacity map. */
void frame_light_view(satf_renderer *r);
/* Pixel rectangle (x, y, w, h) the scene bounds can cover. */
void frame_screen_box(const satf_renderer *r, const float viewproj[16],
                      int box[4]);
/* Instance indices far to near from the eye (malloc'd; NULL: no memory). */
int *frame_far_to_near(const satf_renderer *r);

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

/* ---- passes.c: GPU passes (Table 1: L, S) ----------------------------- */

/* The deep opacity map from the key light. */
/* Draws the hair of a deep opacity map into the bound target: its depth
 * (opacity 0, colour writes off) or its opacity into the slabs (1: the
 * first-hair depth on texture unit 1; passes_dom_uniforms sets a
 * program's u_dom_depth and u_dom_slab). */
typedef void (*passes_dom_hair_fn)(satf_renderer *r, void *ctx, int opacity);
/* The deep opacity map of any hair: the light's view, both passes with the
 * meshes as opaque occluders, the state restored. */
void passes_dom_with(satf_renderer *r, passes_dom_hair_fn hair, void *ctx);
void passes_dom_uniforms(const satf_renderer *r, GLuint prog);
void passes_dom(satf_renderer *r);
/* The largest move, in texels across the light or slabs along it, of any
 * cluster control point (or radius) since the map was drawn; INFINITY when
 * it cannot be measured (no map, or other clusters). */
float passes_dom_hair_move(const satf_renderer *r);
/* Per-pixel fragment arrays, then their sorted composite; returns the
 * largest number of fragments a pixel received and sets *overflow to the
 * pixels that received more than r->slots. Without `nearest` each pixel
 * keeps the first r->slots fragments to arrive. `nearest` (r->keys_tex
 * allocated) follows a call without it for the same frame: the pixels that
 * received more than r->slots there are filled again with their r->slots
 * nearest fragments, whatever their arrival order; the others keep
 * theirs (and the counts, so the figures are that call's). */
GLuint passes_lists(satf_renderer *r, satf_aov aov, const float viewproj[16],
                    int nearest, long *fragments, long *overflow);
/* Clusters drawn far to near with "over" blending. */
satf_status passes_ordered(satf_renderer *r, satf_aov aov,
                           const float viewproj[16], satf_error *err);
/* A triangle covering the viewport, drawn with the bound program. */
void passes_fullscreen(const satf_renderer *r);
/* What other drawing paths (baseline.c, strands.c) share with the
 * clusters' passes: the opaque meshes with `prog`; the material, lights,
 * effects and deep opacity map of a shading program; clearing the frame
 * and drawing the lit meshes; hair tested against the meshes' depth
 * without writing it. */
void draw_meshes(const satf_renderer *r, GLuint prog, const float viewproj[16]);
void set_shading_uniforms(const satf_renderer *r, GLuint p, satf_aov aov);
void begin_frame(const satf_renderer *r, satf_aov aov,
                 const float viewproj[16]);
void hair_depth_test(int on);
/* The eye and every light (xyz, w: 0 direction, 1 position) in world
 * space: u_eye and u_light_vec of a program shading in world space. */
void passes_world_lights(const satf_renderer *r, GLuint p);

/* ---- strands.c: the strand reference path ----------------------------- */

/* A frame of the strands (satf_renderer_set_strands) in the clusters'
 * place; with refresh 0 the deep opacity map is reused. */
satf_status strands_render_frame(satf_renderer *r, satf_aov aov, int refresh,
                                 satf_frame_timing *timing, satf_error *err);
void strands_release(satf_renderer *r);
/* A set of strands on the GPU as camera-facing ribbons: n strands of
 * counts[i] points (xyz), each point's width (thickness, or default_width
 * when thickness is NULL); with `list` also the program that writes into
 * the per-pixel arrays. *out is NULL for n = 0. */
satf_status strands_gpu_create(int n, const int *counts, const float *xyz,
                               const float *thickness, float default_width,
                               int list, strands_gpu **out, satf_error *err);
void strands_gpu_destroy(strands_gpu *s);
/* Segments in the order of their strands (strand i's segments follow
 * strand i - 1's), for draws of ranges and for the per-pixel arrays, which
 * need no order. */
void strands_gpu_in_order(strands_gpu *s);
size_t strands_gpu_segments(const strands_gpu *s);
/* The strands' median width (diameter, scene units); 0 for NULL. */
float strands_gpu_width(const strands_gpu *s);
/* The shading program, every fragment (whole or partly covered) blended
 * "over" (list_mode -1) or into the per-pixel arrays in that mode of
 * passes_lists, bound with the frame's material, lights and view. */
void strands_gpu_begin(const satf_renderer *r, strands_gpu *s, satf_aov aov,
                       const float viewproj[16], int list_mode);
void strands_gpu_draw(const strands_gpu *s, size_t first, size_t count);
/* Binds the shading program of strands_gpu_begin again (list_mode -1),
 * its uniforms as that call left them. */
void strands_gpu_use(const strands_gpu *s);
/* The depth of the fragments the strands cover whole (opaque: what lies
 * behind them in a pixel is hidden) written into the bound framebuffer's
 * depth; 0 if no strand is a pixel wide (nothing written). */
int strands_gpu_opaque_depth(const satf_renderer *r, const strands_gpu *s,
                             const float viewproj[16]);
/* The strands into the bound deep opacity map (passes_dom_hair_fn). */
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
 * passes_lists) or into the bound deep opacity map. */
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
/* Instance i's strands blended "over" (passes_ordered's order), with the
 * program of sparse_ordered_begin left bound; 0 if it is not sparse (it is
 * drawn as a cluster). */
int sparse_ordered(satf_renderer *r, int i);

/* ---- baseline.c: the --no-satf path (Scheuermann 2004, paper 002) ----- */

/* A frame of paper 002's method in SATF's place (effects.satf off): no
 * database; with refresh 0 the deep opacity map is reused. */
satf_status baseline_frame(satf_renderer *r, satf_aov aov, int refresh,
                           satf_frame_timing *timing, satf_error *err);
void baseline_release(satf_renderer *r);
/* Ambient occlusion of layer k (0 innermost) of `layers` whose texture has
 * mean alpha `mean_alpha`. */
float baseline_layer_occlusion(float mean_alpha, int k, int layers);

#endif
