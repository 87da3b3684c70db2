/* The light's pass of the deep opacity maps (opacity_map.glsl), one light (shadow_light) at a time into
 * its tile. OPACITY_PASS 0: the depth of the hair from the light, the nearest kept by the depth test.
 * OPACITY_PASS 1 (additive blending, no depth test): the fragment's optical depth (hairlod/opacity_map.py:
 * a strand's line 2 r over the pixel's width, a thick hair's 4 r N sqrt(1 - x^2) / (pi w)) added to every
 * layer whose boundary lies below it. frame.shadow.x is the strands' radius in world units. */
void main()
{
  if (!selected_at_draw_level()) {
    discard;
  }
  float depth = light_depth(shadow_light, v_position);
#if OPACITY_PASS == 0
  fragColor = vec4(depth, 0.0, 0.0, 1.0);
#else
  float first = texelFetch(depth_map, ivec2(gl_FragCoord.xy), 0).r;
  float tau;
  if (v_ellipse.z > 0.0) {
    /* The strip is drawn `v_widen` times wider than the silhouette where that is under a pixel: the
     * strands spread over the drawn width, keeping their 2 r N across it. */
    float widen = max(v_widen, 1.0);
    float x = clamp(v_across / widen, -1.0, 1.0);
    tau = 4.0 * frame.shadow.x * v_cluster.x * sqrt(max(1.0 - x * x, 0.0)) / (HAIRLOD_PI * v_ellipse.z * widen);
  }
  else {
    tau = 2.0 * frame.shadow.x / max(light_pixel_size(shadow_light, depth), 1e-30);
  }
  tau = min(tau, OPACITY_MAX_PIXEL_DEPTH);
  float spacing = frame.light_shadow[shadow_light].z;
  fragColor = tau * step(vec4(depth), vec4(first) + OPACITY_LAYER_STEPS * spacing);
#endif
}
