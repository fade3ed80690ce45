// Directional lights shared by the lit surfaces (included by cloth.frag and
// obstacle.frag). Colours are linear; to_display converts for the framebuffer
// with gamma 2 (square root), close to sRGB and much cheaper than pow() on llvmpipe.
const int MAX_LIGHTS = 4;
uniform int u_light_count;
uniform vec3 u_light_to[MAX_LIGHTS];        // unit vector from the surface towards each light
uniform vec3 u_light_radiance[MAX_LIGHTS];  // colour * intensity, linear
uniform vec3 u_eye;                         // camera position, world

vec3 to_display(vec3 linear_color) {
  return sqrt(clamp(linear_color, 0.0, 1.0));
}

// Blinn-Phong shading of a point with unit normal n (facing the viewer's side).
// key_visibility scales light 0, the key light (0 where it is shadowed).
vec3 shade(vec3 albedo, vec3 n, vec3 position, float shininess, float specular,
           float key_visibility) {
  vec3 to_eye = normalize(u_eye - position);
  // Soft sky light from above and a darker bounce from below, so unlit sides keep their form.
  vec3 ambient = mix(vec3(0.030, 0.028, 0.026), vec3(0.075, 0.080, 0.090), 0.5 + 0.5 * n.z);
  vec3 color = albedo * ambient;
  for (int i = 0; i < u_light_count; ++i) {
    vec3 l = u_light_to[i];
    float diffuse = max(dot(n, l), 0.0);
    float highlight = 0.0;
    if (diffuse > 0.0) {
      highlight = specular * pow(max(dot(n, normalize(l + to_eye)), 0.0), shininess);
    }
    float visibility = (i == 0) ? key_visibility : 1.0;
    color += u_light_radiance[i] * visibility * (albedo * diffuse + vec3(highlight));
  }
  return color;
}
