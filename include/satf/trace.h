/* trace.h - planar ray tracing of a generalized sector into HRIR records
 * (SATF paper sec. 5.1, eq. 5).
 *
 * Angles are azimuths in the sector's plane, measured from the sector's
 * outward direction (+x) towards increasing phase (+y): theta_v points from
 * the sector to the viewer, theta_l from the sector to the light.
 *
 * Record layout. Rays are parallel, travelling along -(cos theta_v,
 * sin theta_v). Sample j of an n-sample record is the ray through the
 * projected position p_j = pmin + (j + 0.5) (pmax - pmin) / n along the
 * screen axis e = (-sin theta_v, cos theta_v), where [pmin, pmax] is the
 * sector's extent projected on e (satf_trace_extent). A renderer lays a
 * record across an HSV by projecting the fragment's sector-plane position
 * onto e the same way. */
#ifndef SATF_TRACE_H
#define SATF_TRACE_H

#include "satf/sector.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct satf_trace_params {
  int width;          /* samples per HRIR (rays across the projected width) */
  float extinction;   /* opacity per unit density per unit length */
  float ambient;      /* Phong k_a */
  float diffuse;      /* Phong k_d */
  float specular;     /* Phong k_s */
  float shininess;    /* Phong exponent */
  float epsilon;      /* stop when accumulated alpha > 1 - epsilon */
  int self_shadow;    /* attenuate light by the density towards it */
  float smooth_ratio; /* Gaussian smoothing width / strand width (1.5) */
} satf_trace_params;

satf_trace_params satf_trace_params_default(void);
satf_status satf_trace_params_check(const satf_trace_params *p,
                                    satf_error *err);

/* Extent [pmin, pmax] of the sector shape projected on the screen axis. */
void satf_trace_extent(const satf_sector_shape *shape, float theta_v,
                       float *pmin, float *pmax);

/* Eq. 5: one front-to-back step. Updates the ray's accumulated reflectance
 * and opacity with a sample of opacity alpha and reflectance re. */
void satf_accumulate(float *acc_re, float *acc_alpha, float alpha, float re);

/* Opacity of a march step of length ds through density rho. */
float satf_step_opacity(float extinction, float rho, float ds);

/* Phong reflectance of a point with (unnormalised) normal n, light and view
 * directions l, v (unit, in the plane), lit by transmittance T. */
float satf_phong(const satf_trace_params *p, const float n[2], const float l[2],
                 const float v[2], float transmittance);

/* Traces one HRIR: re[width] and alpha[width]. */
satf_status satf_trace_hrir(const satf_sector *sector,
                            const satf_trace_params *p, float theta_v,
                            float theta_l, float *re, float *alpha,
                            satf_error *err);

/* Traces the HRIRs of every view x light pair on uniform grids of n_view and
 * n_light azimuths (k * 2 pi / n). Output record (iv, il) starts at
 * ((iv * n_light) + il) * width in re and alpha. Reuses work shared by the
 * pairs; equal, value for value, to calling satf_trace_hrir per pair. */
satf_status satf_trace_all(const satf_sector *sector,
                           const satf_trace_params *p, int n_view, int n_light,
                           float *re, float *alpha, satf_error *err);

#ifdef __cplusplus
}
#endif
#endif
