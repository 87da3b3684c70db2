/* Whether this fragment's segment was selected at the batch's level: the selection texture holds the
 * level per segment (x) and L0 cluster (y), -1 for culled clusters (Huang 2025 Eq. 16).
 * v_select_point runs from k to k + 1 along segment k. Programs drawing only segments all at their
 * level (HAIRLOD_ALL_AT_DRAW_LEVEL) have neither the test nor its varyings. */
#ifndef HAIRLOD_ALL_AT_DRAW_LEVEL
bool selected_at_draw_level()
{
  int segment = clamp(int(floor(v_select_point)), 0, textureSize(selection_levels, 0).x - 1);
  return int(texelFetch(selection_levels, ivec2(segment, v_select_cluster), 0).r) == draw_level;
}
#endif
