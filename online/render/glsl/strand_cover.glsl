/* strand_cover.glsl - the fraction of a pixel a strand covers: the
 * overlap of the pixel (a unit box filter across the strand) with the
 * strand's [-w/2, w/2] band, from the pixel centre's distance d to the
 * centre line (strand_vs.glsl). A strand thinner than a pixel covers w at
 * most; a wide one covers 1 inside and ramps over its edge's pixel. */
float strand_coverage(float d, float w) {
  d = abs(d);
  return clamp(min(d + 0.5, 0.5 * w) - max(d - 0.5, -0.5 * w), 0.0, 1.0);
}
