/* shaders.h - GLSL sources of the online renderer (OpenGL 4.3 core). */
#ifndef SATF_ONLINE_SHADERS_H
#define SATF_ONLINE_SHADERS_H

extern const char *const satf_glsl_layer_vs;    /* shell layer vertices */
extern const char *const satf_glsl_shade_fs;    /* eq. 8-13 + list append */
extern const char *const satf_glsl_dom_fs;      /* deep opacity map slabs */
extern const char *const satf_glsl_depth_fs;    /* light-space depth only */
extern const char *const satf_glsl_fullscreen_vs;
extern const char *const satf_glsl_resolve_fs;  /* eq. 14, sorted */
extern const char *const satf_glsl_display_fs;  /* linear -> sRGB blit */

/* Fragments kept per pixel by the resolve pass. */
#define SATF_MAX_FRAGMENTS 64

#endif
