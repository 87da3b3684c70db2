void main()
{
  fragment_colour = vec4(shade, 1.0);
}
