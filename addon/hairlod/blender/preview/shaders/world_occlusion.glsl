/* The hair's own occlusion of the world (hairlod/world_occlusion.py is the reference): the optical
 * depth from p (object space) out to the world along each of HAIR_WORLD_DIRECTIONS (self_shadow.glsl),
 * through the strands' density on a grid, strength included. The 3D texture world_depths holds 4
 * directions a texel, in 4 groups of the grid's z slices one after the other (world_occlusion_texture.py);
 * read trilinear between the voxels' centres, clamped to the outer ones. lower_scale = (the grid's lower
 * corner, strength x its depth factor), extent = the grid's extent: the frame's world_grid_lower and
 * world_grid_extent.xyz. */
void world_grid_depths(vec3 p, vec4 lower_scale, vec3 extent, out float tau[14])
{
  ivec3 texels = textureSize(world_depths, 0);
  vec3 size = vec3(float(texels.x), float(texels.y), float(texels.z / 4));
  vec3 cell = clamp((p - lower_scale.xyz) / extent, 0.5 / size, 1.0 - 0.5 / size);
  for (int g = 0; g < 4; ++g) {
    vec4 depths = texture(world_depths, vec3(cell.xy, (float(g) + cell.z) * 0.25)) * lower_scale.w;
    for (int c = 0; c < 4 && 4 * g + c < 14; ++c) {
      tau[4 * g + c] = depths[c];
    }
  }
}
