/* The preview's hair layer into the viewport (hair_layer.py): each pixel's mean over the layer's
 * samples, and its depth taken from the hair's fitted projection back to the viewport's
 * (hairlod/depth_range.py, whose viewport_depth is the same formula), so that the scene's objects hide
 * the hair as before. hair_colour: the samples' colours summed (rgb) and how many held hair (a);
 * hair_depth: their fitted window depths summed (r); samples: how many were drawn. The colour is the
 * mean over the samples holding hair, its alpha the share of samples that do (blended over the
 * viewport), the depth their mean. planes: (A, B) fitted and (A, B) of the viewport, row 2 of each
 * projection; perspective: 1 or 0. */
void main()
{
  ivec2 texel = clamp(ivec2(uv * vec2(textureSize(hair_depth, 0))), ivec2(0), textureSize(hair_depth, 0) - 1);
  vec4 sum = texelFetch(hair_colour, texel, 0);
  if (sum.a < 0.5) {
    discard;
  }
  float depth = texelFetch(hair_depth, texel, 0).r / sum.a;
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
  fragColor = vec4(sum.rgb / sum.a, min(sum.a / samples, 1.0));
}
