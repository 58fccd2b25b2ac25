/* dom.h - the deep opacity map (Yuksel & Keyser 2008) from a light, the
 * key light's and in the physical mode the fill light's (private to
 * online/render): its targets, the light's view and slabs, and
 * what it was drawn with, so a drawing path can keep it while nothing it
 * reads has changed. dom.c owns it and the drawing sequence every path
 * shares (draw.h: the hair's first depth with the meshes as occluders,
 * then its optical depth summed into four slabs, with the first and last
 * hair's depths per texel beside them); the paths draw their own hair into
 * it through a dom_hair_fn. */
#ifndef SATF_RENDER_DOM_H
#define SATF_RENDER_DOM_H

#include "satf/gl.h"
#include "satf/render.h"
#include "view.h"

/* Side of the deep opacity map, in texels. */
#define DOM_SIZE 512
/* The most a cluster's control point may move, in texels across the light
 * or slabs along it, before the deep opacity map is drawn again
 * (cluster_dom.c; satf_renderer_set_shadow_move). */
#define DOM_MOVE_TOL 1.0f

/* Draws the hair of the map into the bound target: its depth (opacity 0,
 * colour writes off) or its opacity into the slabs (1: the first-hair
 * depth on texture unit 1; dom_uniforms sets a program's uniforms). */
typedef void (*dom_hair_fn)(satf_renderer *r, void *ctx, int opacity);

typedef struct dom_map {
  /* depth: the first hair's depth (the depth pass); opacity: the slabs'
   * optical depths (colour 0) and (-first, last) hair's depth (colour 1,
   * what look-ups read for both) */
  satf_gl_target *depth, *opacity;
  /* this frame's orthographic view along the key light, and the depth of
   * one slab in its depth units (dom_place) */
  float viewproj[16], slab;
  /* whether the map holds a drawing, and the view and slab it was drawn
   * with (a path that keeps the map draws with those) */
  int valid;
  float drawn_viewproj[16], drawn_slab;
  /* the hair that drew it (a drawing path's dom_hair_fn and its ctx): a
   * path keeps only a map of its own hair */
  dom_hair_fn drawn_hair;
  const void *drawn_ctx;
  long reuses; /* frames that reused it */
  /* the maps' alpha, which the map reads, follows the eye's azimuth: the
   * eye when the map was drawn, whether maps were uploaded since, and how
   * far (radians, seen from any cluster) the eye may turn before the map
   * is drawn again for them (INFINITY by default: never for the eye
   * alone, 0: whenever a map changed) */
  float eye[3], eye_tol;
  int maps_stale;
  /* the map is kept across scene changes while no cluster's control point
   * has moved more than move_tol texels across the light or slabs along
   * it (points: each one's world xyz and radius when the map was drawn,
   * npoints of them); move_tol < 0: the exact rule (drawn again after
   * every satf_renderer_set_scene) */
  float move_tol;
  float *points;
  int npoints;
  float light[4];  /* its light's vector when the map was drawn */
  int light_index; /* the scene light it is drawn along (0: the key) */
} dom_map;

/* Its targets, filtered: the map is coarse, and its texels must not show. */
satf_status dom_create(dom_map *d, satf_error *err);
void dom_release(dom_map *d);
/* Records that d was just drawn by `hair` (ctx) with its present view and
 * slab, which a path compares before it keeps the map. */
void dom_mark_drawn(dom_map *d, dom_hair_fn hair, const void *ctx);
/* The fill light's map takes the key's place while it is drawn (the
 * drawing paths draw r->dom): swaps the two, the first's tolerances
 * (eye_tol, move_tol) copied into the second first. */
void dom_swap(dom_map *a, dom_map *b);
/* d->viewproj along v's light d->light_index over the scene bounds, and d->slab
 * a third of the mean macro-cluster radius `cluster_r` deep
 * (dom_cluster_radius), never thinner than hair_width (a hair's diameter;
 * 0: no floor). */
void dom_place(dom_map *d, const view *v, float cluster_r, float hair_width);
/* The mean radius at their root of the scene's first nprotos
 * prototypes. */
float dom_cluster_radius(const satf_scene *scene, int nprotos);
/* Binds `prog` and sets its u_dom_depth (texture unit 1) and u_dom_slab. */
void dom_uniforms(const dom_map *d, GLuint prog);

#endif
