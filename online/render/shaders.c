/* shaders.c - the GLSL of the online renderer under its C names
 * (shaders.h). The text lives in the .glsl files of glsl/, embedded at
 * build time by glsl/embed.cmake as the constants of glsl_text.c (one per
 * file, includes expanded): edit the .glsl files. */
#include "shaders.h"

extern const char glsl_text_lighting[], glsl_text_layer_vs[],
    glsl_text_cluster_vs[], glsl_text_shade_fs[], glsl_text_dom_fs[],
    glsl_text_depth_fs[], glsl_text_fullscreen_vs[], glsl_text_resolve_fs[],
    glsl_text_display_fs[], glsl_text_mesh_vs[], glsl_text_mesh_fs[],
    glsl_text_empty_fs[], glsl_text_dom_mesh_fs[], glsl_text_strand_vs[],
    glsl_text_strand_fs[], glsl_text_strand_dom_fs[], glsl_text_baseline_vs[],
    glsl_text_baseline_fs[], glsl_text_baseline_lighting[],
    glsl_text_accum_fs[], glsl_text_fiber[], glsl_text_fiber_cluster[];

const char *const satf_glsl_lighting = glsl_text_lighting;
const char *const satf_glsl_layer_vs = glsl_text_layer_vs;
const char *const satf_glsl_cluster_vs = glsl_text_cluster_vs;
const char *const satf_glsl_shade_fs = glsl_text_shade_fs;
const char *const satf_glsl_dom_fs = glsl_text_dom_fs;
const char *const satf_glsl_depth_fs = glsl_text_depth_fs;
const char *const satf_glsl_fullscreen_vs = glsl_text_fullscreen_vs;
const char *const satf_glsl_resolve_fs = glsl_text_resolve_fs;
const char *const satf_glsl_display_fs = glsl_text_display_fs;
const char *const satf_glsl_accum_fs = glsl_text_accum_fs;
const char *const satf_glsl_mesh_vs = glsl_text_mesh_vs;
const char *const satf_glsl_mesh_fs = glsl_text_mesh_fs;
const char *const satf_glsl_empty_fs = glsl_text_empty_fs;
const char *const satf_glsl_dom_mesh_fs = glsl_text_dom_mesh_fs;
const char *const satf_glsl_baseline_vs = glsl_text_baseline_vs;
const char *const satf_glsl_baseline_fs = glsl_text_baseline_fs;
const char *const satf_glsl_baseline_lighting = glsl_text_baseline_lighting;
const char *const satf_glsl_strand_vs = glsl_text_strand_vs;
const char *const satf_glsl_strand_fs = glsl_text_strand_fs;
const char *const satf_glsl_strand_dom_fs = glsl_text_strand_dom_fs;
const char *const satf_glsl_fiber = glsl_text_fiber;
const char *const satf_glsl_fiber_cluster = glsl_text_fiber_cluster;
