/* draw.h - what every drawing path's GPU passes share (private to
 * online/render), under the paths: clearing the frame and drawing the lit
 * opaque meshes, the material, lights, effects and deep opacity map of a
 * shading program, hair tested against the meshes' depth, and the deep
 * opacity map's two passes. draw.c owns these; they read the renderer's view,
 * scene, meshes and deep opacity map and call no drawing path. */
#ifndef SATF_RENDER_DRAW_H
#define SATF_RENDER_DRAW_H

#include "dom.h"
#include "satf/gl.h"
#include "satf/render.h"

/* A row-major 4x4 matrix uniform of the bound program. */
void draw_set_mat4(GLuint prog, const char *name, const float m[16]);
/* The opaque meshes with `prog` (per-mesh model and normal matrices). */
void draw_meshes(const satf_renderer *r, GLuint prog, const float viewproj[16]);
/* Binds `p` and sets the material, lights, effects, fragment slots and deep
 * opacity map (texture units 2 and 3) of a shading program. */
void draw_shading_uniforms(const satf_renderer *r, GLuint p, satf_aov aov);
/* The eye and every light (xyz, w: 0 direction, 1 position) in world
 * space: u_eye and u_light_vec of a program shading in world space. */
void draw_world_lights(const satf_renderer *r, GLuint p);
/* u_depth_row of a program writing SATF_AOV_DEPTH (glsl/depth_encode.glsl):
 * minus the world-to-camera matrix's third row, whose product with a world
 * point is its distance along the view axis. */
void draw_depth_row(const satf_renderer *r, GLuint p);
/* Clears the frame to transparent black (every pass is premultiplied over
 * it; the background is composited by whoever shows the image) and draws
 * the opaque meshes, leaving their depth for the hair to test against. */
void draw_begin_frame(const satf_renderer *r, satf_aov aov,
                      const float viewproj[16]);
/* Hair tests against the meshes' depth without writing it (on), or the
 * default depth state again (off). */
void draw_hair_depth_test(int on);
/* Whether the frame draws and reads the fill light's deep opacity map:
 * the physical mode, two lights or more, shadows between clusters on.
 * Cycles shadows every light; the fill left unshadowed lit the side of
 * dense hair away from the key bluer than Cycles (fur 4.0, curls 6.8,
 * the straight curtain 4.4 degrees of chroma at 320x240), and each light
 * rendered alone through the key's map matched Cycles' frame of that
 * light alone within 0.2-2.8 degrees. The lights after the fill share
 * its map (the default rig has two). */
int draw_fill_shadows(const satf_renderer *r);
/* The map of any hair: placed for r's view (dom_place with hair_width),
 * both passes with the meshes as opaque occluders, the state restored;
 * r->dom.valid cleared (whoever drew it, a kept map is gone). */
void draw_dom(satf_renderer *r, float cluster_r, float hair_width,
              dom_hair_fn hair, void *ctx);
/* draw_dom for the key light and, where draw_fill_shadows, the fill's
 * (r->fill_dom, drawn in r->dom's place: dom_swap), each kept instead
 * where the same hair and ctx drew it last at the same place (the light's
 * view over the scene's bounds, the slabs) and it is still valid: a
 * drawing path whose hair moves only when satf_renderer_set_scene or
 * satf_renderer_set_strands clears the maps (the strand path). */
void draw_dom_lights(satf_renderer *r, float cluster_r, float hair_width,
                     dom_hair_fn hair, void *ctx);

#endif
