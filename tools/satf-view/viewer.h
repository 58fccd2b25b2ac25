/* viewer.h - satf-view's interactive window: the camera and light under the
 * mouse, the effect keys, animation playback and saving frames. */
#ifndef SATF_TOOLS_VIEWER_H
#define SATF_TOOLS_VIEWER_H

#include "frontend.h"
#include "satf/gl.h"

/* The mouse and keys, as --help, the start and the H key list them. */
extern const char viewer_keys[];

typedef struct viewer_opts {
  satf_scene_effects off; /* effects switched off on the command line */
  int composite;          /* satf_composite */
  const char *prefix;     /* saved frames are PREFIX-NNNN.exr/.png */
  const char *shot;       /* --screenshot PATH, or NULL */
  long frames;            /* frames drawn before the screenshot */
  long bench;             /* --bench N: N orbiting frames, a Table 1 row */
  const char *name;       /* the scene's name in that row */
  int width, height;      /* the renderer's size if the window reports none */
} viewer_opts;

/* Renders fe's scene into win until the window closes (or, with a
 * screenshot, until it is written; with --bench, after its frames and the
 * row printed). Creates and destroys the renderer. The T key loads fe's
 * source strands the first time it is pressed (fe->strands). */
satf_status viewer_run(satf_gl_window *win, satf_frontend *fe,
                       const viewer_opts *opts, satf_error *err);

#endif
