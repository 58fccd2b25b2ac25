/* renderer.h - the online phase of SATF (paper sec. 6) on OpenGL 4.3+:
 * per frame, database look-ups build each shell layer's re/alpha/s-maps
 * (maps.h), layers are lit with Kajiya-Kay diffuse and two shifted
 * highlights, shadowed by the s-maps (eq. 12) and a deep opacity map from
 * the key light, and composited order-independently (eq. 14) through
 * per-pixel fragment lists. The caller owns the GL context (headless EGL or
 * a GLFW window) and keeps it current. */
#ifndef SATF_ONLINE_RENDERER_H
#define SATF_ONLINE_RENDERER_H

#include "online/image.h"
#include "satf/db.h"
#include "satf/scene.h"

typedef struct satf_renderer satf_renderer;

typedef enum satf_aov {
  SATF_AOV_BEAUTY = 0,
  SATF_AOV_DIFFUSE,
  SATF_AOV_SPEC_I,
  SATF_AOV_SPEC_II,
  SATF_AOV_SHADOW,
  SATF_AOV_ALPHA,
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
} satf_frame_timing;

typedef struct satf_render_stats {
  long clusters, layers, strands, hsvs, macro_clusters, prototypes_shared;
} satf_render_stats;

/* Builds clusters, shells, meshes, density features and GL resources.
 * `threads` = 0 uses all cores. */
satf_status satf_renderer_create(const satf_scene *scene, const satf_db *db,
                                 int width, int height, int threads,
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
satf_composite satf_renderer_composite(const satf_renderer *r);

/* Renders one frame of `aov` into the renderer's RGBA16F target. */
satf_status satf_renderer_render(satf_renderer *r, satf_aov aov,
                                 satf_frame_timing *timing, satf_error *err);
/* The target's colour texture (linear RGB, A = hair coverage). */
unsigned satf_renderer_texture(const satf_renderer *r);
unsigned satf_renderer_framebuffer(const satf_renderer *r);

/* Renders the beauty pass (and with aovs != 0 every AOV) into a new image
 * with channels R G B A (colour composited over the background, A the hair
 * coverage) and, for AOVs, diffuse.R/G/B, specI.R/G/B, specII.R/G/B,
 * shadow, alpha. */
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

/* Writes every shell layer mesh of every prototype (OpenMesh, by the
 * extension of `path`: .obj or .ply) as PATH-m<macro>-l<layer>.EXT; sets
 * *written to the number of files. */
satf_status satf_renderer_export_meshes(const satf_renderer *r,
                                        const char *path, int *written,
                                        satf_error *err);

/* Draws the target to the bound framebuffer (viewport already set),
 * converting linear to sRGB. */
void satf_renderer_present(satf_renderer *r);

#endif
