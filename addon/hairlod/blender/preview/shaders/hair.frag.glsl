/* The LoD preview's hair into its hair layer (hair_layer.py): fragColor.a holds the window depth there,
 * and strandPosition says which pixels the strands' deferred shading is left to.
 * shading_mode 0: thick hairs shaded here (hair_radiance, hair_shading.glsl); strands
 * (HAIRLOD_DEFERRED_STRANDS) only leave their unit tangent in fragColor.rgb and their position, w = 1,
 * in strandPosition: the depth test keeps the nearest, and the layer's strand pass shades each such pixel
 * once (strand_shading.frag.glsl), where shading every strand fragment shaded each pixel several times over.
 * shading_mode 1: the level's colour, darkened towards the silhouette.
 * The scene-linear radiance goes through the scene's view transform (view_transform.glsl). */

void main()
{
  /* Only the segments Huang 2025 Eq. 16 selected at this batch's level (selection.glsl); batches whose
   * every segment is at it skip the test (HAIRLOD_ALL_AT_DRAW_LEVEL): without a discard the GPU can
   * test depth before shading. */
#ifndef HAIRLOD_ALL_AT_DRAW_LEVEL
  if (!selected_at_draw_level()) {
    discard;
  }
#endif
  strandPosition = vec4(0.0);
  float across = clamp(v_across, -1.0, 1.0);
  if (shading_mode == 1) {
    float facing = sqrt(max(1.0 - across * across, 0.0));
    fragColor = vec4(level_colour.rgb * (0.45 + 0.55 * facing), gl_FragCoord.z);
    return;
  }
#ifdef HAIRLOD_DEFERRED_STRANDS
  fragColor = vec4(normalize(v_tangent), gl_FragCoord.z);
  strandPosition = vec4(v_position, 1.0);
#else
  vec3 radiance = hair_radiance(v_position, normalize(v_tangent), normalize(v_to_camera), across, v_ellipse, v_cluster);
  fragColor = vec4(view_transform(radiance), gl_FragCoord.z);
#endif
}
