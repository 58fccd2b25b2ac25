/* sequence.h - batch rendering of a range of animation frames to OpenEXR
 * (SATF Fig. 8): one snapshot per frame (satf/anim.h) switched into the
 * renderer so only what moves is rebuilt, each frame written through a
 * temporary file so a killed batch never leaves a partial frame, resuming
 * by skipping frames already on disk, and a contact sheet of thumbnails. */
#ifndef SATF_ONLINE_SEQUENCE_H
#define SATF_ONLINE_SEQUENCE_H

#include "online/renderer.h"

typedef struct satf_sequence_opts {
  int first, last;           /* inclusive frame range */
  const char *exr_pattern;   /* printf pattern with one integer, e.g.
                                out/frame_%04d.exr; may be NULL */
  const char *png_pattern;   /* the same for PNG previews; may be NULL */
  const char *contact_sheet; /* PNG of all frames' thumbnails; may be NULL */
  int resume;                /* skip frames whose EXR already reads back */
  int aovs;
  int quiet;
} satf_sequence_opts;

typedef struct satf_sequence_stats {
  int rendered, skipped;
  double seconds;
  satf_frame_timing mean; /* over rendered frames */
} satf_sequence_stats;

/* Checks that a pattern holds exactly one integer conversion (%d, %04d,
 * %5d ...) and no other %. */
satf_status satf_sequence_check_pattern(const char *pattern, satf_error *err);

/* Renders the range with `r`, which was created from `scene` (the
 * animated scene, outliving the call). */
satf_status satf_sequence_render(satf_renderer *r, const satf_scene *scene,
                                 const satf_sequence_opts *opts,
                                 satf_sequence_stats *stats, satf_error *err);

#endif
