/* import_prepare.h - strands made ready for the fit: turned into the
 * scene's axes (--up, --transform) and rid of what no cylinder fits. */
#ifndef SATF_IMPORT_PREPARE_H
#define SATF_IMPORT_PREPARE_H

#include <stddef.h>

#include "satf/import.h"

/* The row-major matrix the options put the hair in the scene with: the
 * --up conversion (Z-up: (x, y, z) -> (x, z, -y)) followed by --transform.
 * Returns 0 when it is the identity. */
int import_hair_matrix(const satf_import_options *o, float m[16]);

/* The same conversion for the head mesh: --up, then --mesh-transform. */
void import_mesh_matrix(const satf_import_options *o, float m[16]);

/* Replaces *s by its strands moved by m (identity: NULL), thickness scaled
 * by the transform's mean scale. With clean, a point equal to the one
 * before it is merged into it (*merged counts them) and a strand left with
 * one point (all its points coincide: no length) is dropped (*dropped);
 * a set with nothing left is an error naming path. */
satf_status import_prepare_strands(satf_strand_set **s, const float *m,
                                   int clean, const char *path, int *dropped,
                                   size_t *merged, satf_error *err);

#endif
