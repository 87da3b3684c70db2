/* The scene's colour management for the preview (view_transform.py): the scene-linear radiance a fragment
 * shades goes through the scene's view transform (a 3D table, view_lut, over the log shaper of
 * VIEW_SHAPER_LOW and VIEW_SHAPER_HIGH, defined by view_transform.py), and since the viewport's
 * framebuffer encodes what a POST_VIEW handler writes with the sRGB transfer curve, the display value is
 * written sRGB-decoded. */

float srgb_decode(float encoded)
{
  return encoded <= 0.04045 ? encoded / 12.92 : pow((encoded + 0.055) / 1.055, 2.4);
}

vec3 view_transform(vec3 radiance)
{
  vec3 x = clamp(radiance, vec3(0.0), vec3(VIEW_SHAPER_HIGH));
  vec3 u = log2(1.0 + x / VIEW_SHAPER_LOW) / log2(1.0 + VIEW_SHAPER_HIGH / VIEW_SHAPER_LOW);
  float n = float(textureSize(view_lut, 0).x);
  vec3 display = texture(view_lut, (u * (n - 1.0) + 0.5) / n).rgb;
  return vec3(srgb_decode(display.r), srgb_decode(display.g), srgb_decode(display.b));
}
