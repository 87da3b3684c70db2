/* Colour by level: the level's colour, darkened towards the silhouette like a round fibre. */
void main()
{
  float across = clamp(v_across, -1.0, 1.0);
  float facing = sqrt(max(1.0 - across * across, 0.0));
  fragColor = vec4(level_colour.rgb * (0.45 + 0.55 * facing), 1.0);
}
