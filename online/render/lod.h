/* lod.h - the clusters' level of detail (online/render/lod.c):
 * per cluster and frame, from its projected size, how many shell
 * layers the shading pass reads (a continuous level, faded across each
 * band so nothing pops) and which of its prototype's proxies is drawn:
 * the rules, pure functions (lod_frame.c applies them to a renderer).
 * Private to online/render. */
#ifndef SATF_LOD_H
#define SATF_LOD_H

#include <stddef.h>

/* The proxies of a prototype (hierarchy.c builds them, cluster_gpu.c draws
 * them), as index ranges of one buffer: a ring of 12 columns on every HSV
 * row; a thin ring of 6 columns on every row, or on every second; and the
 * deep opacity map's coarse one (12 columns, every fourth row), which the
 * level of detail does not choose. */
enum {
  LOD_PROXY_FULL = 0,
  LOD_PROXY_THIN,
  LOD_PROXY_THIN_HALF_ROWS,
  LOD_PROXY_DOM,
  LOD_PROXIES
};

/* Rows of HSVs each band of proxy p spans, and whether it has the thin
 * ring of columns. */
int lod_proxy_rows(int p);
int lod_proxy_thin(int p);

/* The thresholds, in pixels on screen (their image error and cost:
 * docs/performance.md, "Level of detail"). */
typedef struct lod_params {
  float full_px;    /* clusters at least this wide read every layer */
  float thin_px;    /* clusters at most this wide take the thin ring */
  float sag_px;     /* most a band of two rows may depart from the shell */
  float hysteresis; /* relative margin before a proxy changes back */
} lod_params;

lod_params lod_defaults(void);

/* The continuous level of a cluster width_px wide with `layers` shells:
 * 0 reads every layer; level n + f reads every 2^n-th from the outermost,
 * with the layers every 2^(n+1)-th drops faded by 1 - f; capped where one
 * layer stands for all. */
float lod_level(float width_px, int layers, const lod_params *p);

/* How many layers shell k (0 innermost) of `layers` stands for at `level`
 * (0: not read); they sum to `layers` at every level and are continuous
 * in it. glsl/shade_fs.glsl's lod_read and lod_alpha read and weight the
 * layers the same way. */
float lod_layer_share(float level, int k, int layers);

/* The proxy for a cluster width_px wide whose two-row bands would depart
 * sag_px from its shell, drawn last frame with proxy `current` (-1: none):
 * the thin ring at most thin_px wide, on every second row within sag_px;
 * changed only when the sizes leave the thresholds by p->hysteresis. */
int lod_proxy(float width_px, float sag_px, int current, const lod_params *p);

/* The level where one layer stands for all `layers`: 2^cap >= layers. */
int lod_level_cap(int layers);

/* A prototype's measures for lod_update from its proxy's vertices (n of
 * `stride` floats with the layout of hierarchy.c: position at 0, the
 * section's centre at 8, n1 at 11, A and B at 17, 18; rows of `cols`
 * vertices, st + 1 rows): bounding sphere (centre, radius), widest
 * cross-section, and how far a band of two rows departs from the shell
 * (the middle row's centre from the chord, plus its axis n1 from the
 * normalised mean, times the radius: what linear interpolation across the
 * band misplaces). */
void lod_measure(const float *v, size_t n, int stride, int cols, int st,
                 float sphere[4], float *width, float *sag);

#endif
