/* One triangle over the whole viewport (hair_layer.frag.glsl): uv in [0, 1] over the viewport. */
void main()
{
  uv = 0.5 * position + 0.5;
  gl_Position = vec4(position, 0.0, 1.0);
}
