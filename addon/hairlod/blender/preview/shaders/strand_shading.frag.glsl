/* The strands the hair layer holds, shaded once per pixel (hair_layer.py, shade_strands): where a
 * strand is the nearest hair (strand_positions.w = 1), hair_colour.rgb holds its unit tangent and
 * strand_positions.xyz its position (world space), and it is shaded as hair.frag.glsl shaded it
 * (hair_radiance, hair_shading.glsl, for one hair: HAIRLOD_SINGLE_HAIR); elsewhere the colour drawn is
 * kept. */
void main()
{
  ivec2 texel = ivec2(gl_FragCoord.xy);
  vec4 hair = texelFetch(hair_colour, texel, 0);
  vec4 strand = texelFetch(strand_positions, texel, 0);
  vec3 colour = hair.rgb;
  if (strand.w > 0.5) {
    vec3 to_camera = frame.camera.xyz - strand.xyz * frame.camera.w;
    colour = view_transform(hair_radiance(strand.xyz, hair.rgb, normalize(to_camera), 0.0, vec3(0.0), vec2(1.0)));
  }
  fragColor = vec4(colour, 1.0);
}
