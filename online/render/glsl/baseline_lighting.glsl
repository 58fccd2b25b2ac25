/* baseline_lighting.glsl - Scheuermann 2004 (paper 002) shading terms the
 * baseline's pixel shader (baseline_fs.glsl) adds to the Kajiya-Kay
 * highlights of lighting.glsl. Tests evaluate these functions alone
 * (satf_glsl_baseline_lighting), so this file has no #version line:
 * float scheuermann_diffuse(vec3 n, vec3 l);
 * float scheuermann_noise_mask(float noise, float strength). */

/* Paper 002, "Diffuse lighting": "we use a scaled and biased N.L term:
 * diffuse = max(0, 0.75 x N.L + 0.25). This brightens up the side of the
 * hair facing away from the light" (lerp(0.25, 1, N.L), clamped at 0: the
 * unlit side keeps light down to N.L = -1/3). */
float scheuermann_diffuse(vec3 n, vec3 l) {
  return max(0.0, 0.75 * dot(n, l) + 0.25);
}

/* Paper 002: "We modulate the secondary highlight with a noise texture";
 * noise in [0, 1] from the hair texture's noise channel, strength the
 * scene material's `noise` (the same form as the SATF shader's, so the two
 * methods share the material: mean 1, spread by the strength). */
float scheuermann_noise_mask(float noise, float strength) {
  return mix(1.0, 2.0 * noise, strength);
}
