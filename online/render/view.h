/* view.h - the view a frame is drawn for (private to online/render): the
 * camera, the lights, the scene bounds, the image size and the
 * anti-aliasing sample's sub-pixel offset, and the maths every drawing
 * path shares on them (view-projection, light vectors, screen box). It
 * owns no GL state and calls no other part of the renderer. */
#ifndef SATF_RENDER_VIEW_H
#define SATF_RENDER_VIEW_H

#include "satf/scene.h"

typedef struct view {
  satf_scene_camera camera;
  satf_scene_light lights[SATF_SCENE_MAX_LIGHTS];
  int nlights;
  float lo[3], hi[3]; /* scene bounds, grown by meshes and strands */
  int width, height;  /* image size in pixels */
  float jitter[2];    /* this sample's camera offset in pixels */
} view;

/* The scene's camera, lights and bounds (the state an animation moves). */
void view_take(view *v, const satf_scene *scene);
/* Grows the bounds to hold the box lo..hi. */
void view_grow(view *v, const float lo[3], const float hi[3]);
/* A light as seen from a point: xyz + w (0: direction to it, 1: position). */
void view_light_vector(const satf_scene_light *l, float out[4]);
/* The same in a frame whose inverse transform is inv. */
void view_light_local(const float inv[16], const satf_scene_light *l,
                      float out[4]);
/* colour x intensity of every light, 3 floats each. */
void view_light_colors(const view *v, float *col);
/* Centre and radius (a little more) of the scene bounds. */
float view_radius(const view *v, float centre[3]);
/* The camera's view (world to camera) and projection, without the
 * sample's jitter; without explicit clip planes they hug the scene
 * bounds. */
void view_matrices(const view *v, float look[16], float proj[16]);
/* The camera's view-projection with the sample's jitter; without explicit
 * clip planes they hug the scene bounds. */
void view_camera(const view *v, float viewproj[16]);
/* An orthographic view along light `light`'s direction covering the scene
 * bounds; *radius: the bounds' radius (its depth range is 2 radius). */
void view_light_map(const view *v, int light, float viewproj[16],
                    float *radius);
/* Pixel rectangle (x, y, w, h) the scene bounds can cover; the whole frame
 * when a corner of the bounds is behind the eye. */
void view_screen_box(const view *v, const float viewproj[16], int box[4]);

#endif
