/* path.h - the renderer's drawing paths (private to online/render). A
 * frame is the renderer's view, the hierarchy and the scene drawn by one
 * path, chosen once a frame (renderer.c): the SATF clusters (clusters.c),
 * the source strands they approximate (strands.c), or Scheuermann 2004's
 * textured patches (baseline.c, SATF Fig. 4a). Each owns its state and
 * calls no other path; the stages under them (view.h, dom.h, lists.h,
 * draw.h) call no path. */
#ifndef SATF_RENDER_PATH_H
#define SATF_RENDER_PATH_H

#include "satf/render.h"

typedef struct render_path {
  const char *name;
  /* builds the path's own state the first time it is chosen (NULL: it has
   * none beyond what the renderer builds with the hierarchy) */
  satf_status (*create)(satf_renderer *r, satf_error *err);
  /* one sample of a frame into r's output target; with refresh 0 what the
   * previous sample made (maps, shadows) is reused (the AOV passes and
   * anti-aliasing samples of one frame) */
  satf_status (*frame)(satf_renderer *r, satf_aov aov, int refresh,
                       satf_frame_timing *timing, satf_error *err);
  /* releases what create and frame made */
  void (*destroy)(satf_renderer *r);
} render_path;

extern const render_path clusters_path;
extern const render_path strands_path;
extern const render_path baseline_path;

#endif
