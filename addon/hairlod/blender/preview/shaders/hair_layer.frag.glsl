/* The preview's hair layer into the viewport (hair_layer.py): each pixel's colour, and its depth
 * taken from the hair's fitted projection back to the viewport's (hairlod/depth_range.py, whose
 * viewport_depth is the same formula), so that the scene's objects hide the hair as before.
 * hair_colour: rgb; hair_depth: in alpha the fitted window depth (1 where no hair): the same texture,
 * or the layer's strands shaded (hair_layer.py) and the layer as drawn; planes: (A, B) fitted and
 * (A, B) of the viewport, row 2 of each projection; perspective: 1 or 0. */
void main()
{
  ivec2 texel = clamp(ivec2(uv * vec2(textureSize(hair_depth, 0))), ivec2(0), textureSize(hair_depth, 0) - 1);
  float depth = texelFetch(hair_depth, texel, 0).a;
  if (depth >= 1.0) {
    discard;
  }
  float ndc = 2.0 * depth - 1.0;
  float z, viewport_ndc;
  if (perspective == 1) {
    z = -planes.y / (ndc + planes.x);
    viewport_ndc = (planes.z * z + planes.w) / -z;
  }
  else {
    z = (ndc - planes.y) / planes.x;
    viewport_ndc = planes.z * z + planes.w;
  }
  gl_FragDepth = clamp(0.5 * viewport_ndc + 0.5, 0.0, 1.0);
  fragColor = vec4(texelFetch(hair_colour, texel, 0).rgb, 1.0);
}
