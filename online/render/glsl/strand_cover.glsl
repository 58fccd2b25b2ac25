/* strand_cover.glsl - the fraction of a pixel a strand covers: the
 * strand's [-w/2, w/2] band seen through the pixel's filter across it,
 * from the pixel centre's distance d to the centre line (strand_vs.glsl).
 * u_pixel_filter (satf_pixel_filter): 0, a one-pixel box: a strand
 * thinner than a pixel covers w at most, a wide one 1 inside, ramping over
 * its edge's pixel; 1, Cycles' default film filter, Blackman-Harris of
 * width 1.5 in Blender's setting, which Cycles stretches to 3 pixels of
 * support: a path tracer's frame spreads a thin strand's coverage over a
 * faint fringe that a box puts on one or two pixels (Bangs_100 at
 * 640x480 against Cycles at 256 samples, coverage IoU 0.77 with the box,
 * 0.88 with this filter, 0.62 with the window over 1.5 pixels only). */
uniform int u_pixel_filter;
const float STRAND_BH_RADIUS = 1.5; /* pixels */

/* The Blackman-Harris window's integral from its left end to x (pixels
 * from its centre), normalised to 1 over its support. */
float strand_bh_cdf(float x) {
  float t = clamp(x / (2.0 * STRAND_BH_RADIUS) + 0.5, 0.0, 1.0);
  const float a0 = 0.35875, a1 = 0.48829, a2 = 0.14128, a3 = 0.01168;
  const float two_pi = 6.28318530718;
  float p = two_pi * t;
  return (a0 * t - a1 * sin(p) / two_pi + a2 * sin(2.0 * p) / (2.0 * two_pi) -
          a3 * sin(3.0 * p) / (3.0 * two_pi)) /
         a0;
}

float strand_coverage(float d, float w) {
  if (u_pixel_filter == 1)
    return clamp(strand_bh_cdf(0.5 * w - d) - strand_bh_cdf(-0.5 * w - d), 0.0,
                 1.0);
  d = abs(d);
  return clamp(min(d + 0.5, 0.5 * w) - max(d - 0.5, -0.5 * w), 0.0, 1.0);
}
