#version 330 core
// Obstacles, compiled in three variants (llvmpipe runs both sides of a branch, so
// unused features are left out at compile time rather than skipped at run time):
//   (none)                   spheres and cylinders: smooth Blinn-Phong shading per pixel
//   PLANE                    plane obstacles: matte, two-sided, fading out at the square's edge
//   PLANE + RECEIVE_SHADOW   the ground, also darkened by the key light's shadow map
#include "lighting.glsl"

in vec3 v_position;
in vec3 v_normal;

out vec4 frag_color;

#ifdef PLANE

in vec4 v_light_clip;
flat in vec3 v_front_lit;
flat in vec3 v_front_shaded;
flat in vec3 v_back_lit;

uniform vec3 u_fade_center;   // world
uniform float u_fade_radius;  // m

#ifdef RECEIVE_SHADOW
uniform sampler2DShadow u_shadow_map;
uniform float u_shadow_texel;  // 1 / shadow map size

// Fraction of the key light reaching this point: 2 x 2 bilinear depth comparisons one
// texel apart, a soft edge about three shadow-map texels wide.
float key_visibility() {
  vec3 p = v_light_clip.xyz / v_light_clip.w * 0.5 + 0.5;
  float depth = min(p.z, 1.0);
  float lit = texture(u_shadow_map, vec3(p.xy + vec2(-0.5, -0.5) * u_shadow_texel, depth));
  lit += texture(u_shadow_map, vec3(p.xy + vec2(0.5, -0.5) * u_shadow_texel, depth));
  lit += texture(u_shadow_map, vec3(p.xy + vec2(-0.5, 0.5) * u_shadow_texel, depth));
  lit += texture(u_shadow_map, vec3(p.xy + vec2(0.5, 0.5) * u_shadow_texel, depth));
  return lit * 0.25;
}
#else
float key_visibility() { return 1.0; }
#endif

void main() {
  vec3 color = gl_FrontFacing ? mix(v_front_shaded, v_front_lit, key_visibility()) : v_back_lit;
  float r = length(v_position - u_fade_center) / u_fade_radius;
  frag_color = vec4(to_display(color), 1.0 - smoothstep(0.45, 0.95, r));
}

#else

uniform vec3 u_albedo;  // linear

void main() {
  vec3 color = shade(u_albedo, normalize(v_normal), v_position, 48.0, 0.25, 1.0);
  frag_color = vec4(to_display(color), 1.0);
}

#endif
