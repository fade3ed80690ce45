// Directional lights shared by the lit surfaces (included by cloth.frag and
// obstacle.frag). Colours are linear; to_display converts for the framebuffer
// with gamma 2 (square root), close to sRGB and much cheaper than pow() on llvmpipe.
// The renderer #defines LIGHT_COUNT (0..4), so the light loop is unrolled at compile time.
#ifndef LIGHT_COUNT
#define LIGHT_COUNT 4
#endif
const int MAX_LIGHTS = 4;
uniform vec3 u_light_to[MAX_LIGHTS];        // unit vector from the surface towards each light
uniform vec3 u_light_radiance[MAX_LIGHTS];  // colour * intensity, linear
uniform vec3 u_eye;                         // camera position, world

vec3 to_display(vec3 linear_color) {
  return sqrt(clamp(linear_color, 0.0, 1.0));
}

// x^shininess. The exponents the shaders use are multiplied out (pow() is exp2(n log2(x))
// on llvmpipe, several times slower); a literal exponent selects its branch at compile time.
float highlight_power(float x, float shininess) {
  if (shininess == 24.0) {
    float x3 = x * x * x;
    float x6 = x3 * x3;
    float x12 = x6 * x6;
    return x12 * x12;
  }
  if (shininess == 48.0) {
    float x3 = x * x * x;
    float x6 = x3 * x3;
    float x12 = x6 * x6;
    float x24 = x12 * x12;
    return x24 * x24;
  }
  return pow(x, shininess);
}

// Blinn-Phong shading of a point with unit normal n (facing the viewer's side).
// key_visibility scales light 0, the key light (0 where it is shadowed).
// Renderer::Impl::lit_ground_color() (renderer.cpp) repeats it for the lit ground: keep
// the two the same.
vec3 shade(vec3 albedo, vec3 n, vec3 position, float shininess, float specular,
           float key_visibility) {
  // Soft sky light from above and a darker bounce from below, so unlit sides keep their form.
  vec3 ambient = mix(vec3(0.030, 0.028, 0.026), vec3(0.075, 0.080, 0.090), 0.5 + 0.5 * n.z);
  vec3 color = albedo * ambient;
#if LIGHT_COUNT > 0
  vec3 to_eye = normalize(u_eye - position);
  for (int i = 0; i < LIGHT_COUNT; ++i) {
    vec3 l = u_light_to[i];
    float diffuse = max(dot(n, l), 0.0);
    float highlight = 0.0;
    if (specular > 0.0) {
      float facing = max(dot(n, normalize(l + to_eye)), 0.0);
      highlight = diffuse > 0.0 ? specular * highlight_power(facing, shininess) : 0.0;
    }
    float visibility = (i == 0) ? key_visibility : 1.0;
    color += u_light_radiance[i] * visibility * (albedo * diffuse + vec3(highlight));
  }
#endif
  return color;
}
