/* atlas.c - the pixel layout shared by the database file and its RGBA atlas
 * (satf/db.h), so tools report sizes without knowing the layout. */
#include "satf/db.h"

void satf_db_atlas_size(const satf_db *db, int *width, int *height) {
  const satf_build_params *p = satf_db_params(db);
  *width = p->n_view * p->trace.width;
  *height = p->samples * p->n_light;
}
