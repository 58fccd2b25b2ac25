/* strands_formats.h - what the strand readers agree on about the formats:
 * the list satf reads, for the error that calls a file's bytes none of
 * them, and the versions a TressFX file can begin with (TressFX has no
 * signature but that float: detection and the TressFX parser use the same
 * range, so bytes detection calls no TressFX file are never reported as a
 * TressFX file of some version). */
#ifndef SATF_IMPORT_STRANDS_FORMATS_H
#define SATF_IMPORT_STRANDS_FORMATS_H

#include <math.h>

#define STRANDS_FORMATS_READ ".hair, .tfx 3.x/4.x, .ply, .obj, .data"

/* TressFX 1.x-5.x: what a file's first float can be when it is TressFX */
static inline int strands_tfx_version_plausible(float version) {
  return isfinite(version) && version >= 1.0f && version < 6.0f;
}

#endif
