/* The view's depth pass: the nearest selected hair's depth per pixel, no colour (the colour mask is off).
 * The shading pass that follows tests depth LESS_EQUAL without writing it, so only the seen fragments
 * are shaded: a software rasteriser (llvmpipe) runs a shader that can discard on every fragment before
 * its depth test, and dense hair covers each pixel many times over. */
void main()
{
  if (!selected_at_draw_level()) {
    discard;
  }
  fragColor = vec4(0.0);
}
