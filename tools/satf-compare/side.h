/* side.h - satf-compare's picture: reference | test | difference side by
 * side in one PNG, so a person sees where two frames disagree. */
#ifndef SATF_TOOLS_COMPARE_SIDE_H
#define SATF_TOOLS_COMPARE_SIDE_H

#include "metrics.h"

/* Linear grey the two frames are composited over, so their coverage shows
 * (18%: a mid grey, sRGB 118). */
#define COMPARE_SIDE_GREY 0.18f

/* Writes a (3 width) x height sRGB PNG to path (through a temporary file
 * renamed into place):
 *   left    ref over grey
 *   middle  test over grey
 *   right   the exposure-normalised luminance difference d = (L_test * s -
 *           L_ref) / w of compare_measure (res: its exposure s and white w)
 *           as a diverging heat map: dark grey where either frame covers
 *           and d = 0, red to yellow where the test is brighter, blue to
 *           cyan where it is darker, full colour at |d| >= 0.5; the mid
 *           grey where neither covers. */
satf_status compare_write_side(const compare_image *ref,
                               const compare_image *test,
                               const compare_result *res, const char *path,
                               satf_error *err);

#endif
