/* features.c - density features of a generalized sector (SATF sec. 5.2). */
#include "satf/db.h"

/* SATF sec. 5.2; see satf_density_features in db.h for how the projected
 * "averages" are read (density-weighted centroids along s and t). */
void satf_density_features(const float *density, int ns, int nt,
                           float out[SATF_FEATURES]) {
  double total = 0.0, ms = 0.0, mt = 0.0;
  for (int j = 0; j < nt; j++) {
    double t = nt > 1 ? (double)j / (double)(nt - 1) : 0.5;
    for (int i = 0; i < ns; i++) {
      double s = ns > 1 ? (double)i / (double)(ns - 1) : 0.5;
      double d = density[j * ns + i];
      total += d;
      ms += d * s;
      mt += d * t;
    }
  }
  out[0] = (float)(total / ((double)ns * (double)nt));
  out[1] = total > 1e-12 ? (float)(ms / total) : 0.5f;
  out[2] = total > 1e-12 ? (float)(mt / total) : 0.5f;
}
