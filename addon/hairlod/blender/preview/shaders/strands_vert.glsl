/* Strand lines in a 3D viewport. Kajiya-Kay diffuse term (Kajiya and Kay 1989): a fibre lit from
 * direction l reflects in proportion to sin(t, l) = sqrt(1 - (t . l)^2), t its unit tangent. The
 * light direction comes in object space, so tangents are used as stored. */
void main()
{
  gl_Position = model_view_projection * vec4(position, 1.0);
  float tangent_length = length(tangent);
  float cos_tl = tangent_length > 0.0 ? dot(tangent, light_direction) / tangent_length : 0.0;
  float diffuse = sqrt(max(1.0 - cos_tl * cos_tl, 0.0));
  float ambient = root_colour.a;
  shade = mix(root_colour.rgb, tip_colour.rgb, along) * (ambient + (1.0 - ambient) * diffuse);
}
