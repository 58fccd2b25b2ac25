/* import_shell.c - the shell sampling a fitted cluster gets (its layers,
 * HSV steps and sectors, and core): what the scene writes for it and what
 * its strands' tracks are sampled at. */
#include <math.h>

#include "import_internal.h"

/* import_choose_shell: the fewest strands a sector of a ring holds */
#define STRANDS_PER_SECTOR 2

satf_scene_shell satf_import_choose_shell(const satf_import_fit *fit) {
  satf_scene_shell sh;
  /* more layers resolve the density of more strands */
  int layers =
      3 + (int)floor(log10(fit->strands > 10 ? fit->strands / 10.0 : 1.0));
  sh.layers = layers < 3 ? 3 : layers > 6 ? 6 : layers;
  /* a few strands fill no volume: two layers hold them */
  if (fit->strands <= 3)
    sh.layers = 2;
  /* HSVs about as long along t as the cluster is wide, but no finer than
   * the strands themselves say anything along t: twice their mean segment
   * count (a thin cluster of few long strands would otherwise get 64 rows
   * of sectors that only repeat one another, and the frame pays for each:
   * the imported ponytail's 363 clusters had 490K HSVs) */
  float r = fit->radius > 0.0f ? fit->radius : 1.0f;
  int st = (int)lroundf(fit->length / r);
  int segments = fit->strands > 0 && fit->points > (size_t)fit->strands
                     ? (int)(fit->points / (size_t)fit->strands) - 1
                     : 4;
  if (st > 2 * segments)
    st = 2 * segments;
  sh.st = st < 8 ? 8 : st > 64 ? 64 : st;
  double ma = 0.0, mb = 0.0;
  for (int j = 0; j < fit->n_radius; j++) {
    ma += fit->a[j];
    mb += fit->b[j];
  }
  double aspect = ma > mb ? ma / mb : mb / ma;
  sh.su = aspect <= 1.5 ? 16 : aspect <= 3.0 ? 24 : 32;
  /* and no more sectors around than the strands fill: at least
   * STRANDS_PER_SECTOR of them for each sector of a ring (su x layers), in
   * steps of 4, down to half the aspect's count (a flat tuft's few sectors
   * along its width still outline it). An HSV emptier than that holds one
   * strand's place, which the records, statistics of many strands, do not
   * show. The shared ponytail's shell clusters hold 30-250 strands, 1-3
   * a sector at the aspect's 16 or 24 around: capped, they keep its
   * SSIM4 against Cycles (0.797) and drop its look-ups after a move from
   * 399K to 238K (C 65-76 -> 44-47 ms, physical, 640x480); a straight
   * curtain's clusters of 300+ strands keep theirs. */
  int fill = (int)(fit->strands / (STRANDS_PER_SECTOR * sh.layers)) / 4 * 4;
  if (sh.su > fill)
    sh.su = fill < sh.su / 2 ? sh.su / 2 : fill;
  /* the core as the strands leave it (satf_import_estimate_density) */
  sh.core = fit->core >= 0.0f && fit->core <= 0.4f ? fit->core : 0.4f;
  /* around a handful of strands, 8 phases resolve them; and no hollow
   * core: a lone strand's track runs along the axis, which the shells
   * between the core and the envelope would never see */
  if (fit->strands <= 8) {
    sh.su = 8;
    sh.core = 0.0f;
  }
  return sh;
}
