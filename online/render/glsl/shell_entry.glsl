/* shell_entry.glsl - where a light's ray towards a point of a cluster
 * enters it: its exit from the outermost ellipse towards the light, in the
 * scaled normal-plane coordinates (P: the point, n1, n2: the ellipse's
 * axes, A, B: its radii), moved out by a tenth of the cluster's radius
 * (the deep opacity map's proxies circumscribe the shell coarsely, and the
 * cluster's own slab must not be counted again). p: the point, l: the
 * unit direction to the light, both in the prototype's frame. No #version
 * line: included (shade_fs.glsl per fragment, cluster_vs.glsl per vertex). */
/* The exit is taken at most the widest chord, 2 max(A, B), from the
 * point: the shell is traced as the local elliptic cylinder, whose exit
 * runs off to infinity as the light turns along the axis, and a look-up
 * past every hair left the cluster unshadowed (the imported ponytail lit
 * from behind: clusters running towards the light at the tie). What lies
 * along the light beyond the chord, the cluster's own hair included, is
 * the map's to count; within it, eq. 12's s-map (the outer layers'
 * alpha) and, in the physical mode, the layers the light crosses on its
 * way through the cluster (shade_fs.glsl: through_layers, scaled to the
 * part of its path within the chord). */
#define SHELL_ENTRY_MAX_CHORDS 1.0
vec3 shell_entry(vec3 p, vec2 P, vec3 l, vec3 n1, vec3 n2, float A, float B) {
  vec2 L = vec2(dot(l, n1) / A, dot(l, n2) / B);
  float a = max(dot(L, L), 1e-12), b = dot(P, L), c = dot(P, P);
  float s = max((-b + sqrt(max(b * b - a * (c - 1.0), 0.0))) / a, 0.0);
  s = min(s, SHELL_ENTRY_MAX_CHORDS * 2.0 * max(A, B));
  return p + (s + 0.1 * max(A, B)) * l;
}
