/* bspline.h - uniform clamped (open-uniform) B-splines on t in [0,1], the
 * curve family of SATF eq. 2 (trajectory T(t) in 3-D, radii A(t), B(t) and
 * twist theta(t) in 1-D).
 *
 * The knot vector is clamped, so the curve starts at the first and ends at
 * the last control point; interior knots are evenly spaced. The degree is
 * cubic when there are at least 4 control points. With fewer, a cubic is not
 * defined, so the degree drops to n - 1: 3 points give a quadratic Bezier
 * curve, 2 a straight segment, 1 a constant. Evaluation is in double
 * precision; control points are the caller's floats, read-only. */
#ifndef SATF_ONLINE_BSPLINE_H
#define SATF_ONLINE_BSPLINE_H

/* The degree used for n control points: min(3, n - 1), and 0 for n < 1. */
int satf_bspline_degree(int n);

/* Evaluates the spline with n control points of dim coordinates each
 * (ctrl[i * dim + c]) at t, clamped to [0,1]. value, d1 (dC/dt) and d2
 * (d2C/dt2) each receive dim doubles; any of them may be NULL. dim must be
 * in 1..4 and n >= 1 (callers validate). */
void satf_bspline_eval(const float *ctrl, int n, int dim, double t,
                       double *value, double *d1, double *d2);

#endif
