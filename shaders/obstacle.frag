#version 330 core
// Obstacles, compiled in variants (llvmpipe runs both sides of a branch, so unused
// features are left out at compile time rather than skipped at run time):
//   (none)                  spheres and cylinders: smooth Blinn-Phong shading per pixel
//   PLANE                   plane obstacles: matte, two-sided, fading out at the square's
//                           edge (alpha, blended over what is behind)
//   PLANE + GROUND          the ground: as a plane, but opaque: it blends itself into the
//                           background gradient (and into a plane obstacle lying in it)
//   PLANE + GROUND + OPAQUE where the ground does not fade (grid cells well inside the
//                           fade's start, or a shadow that stays there): no fade or blend
//   ... + CAST_SHADOW       the key light's shadow on the ground: the casters flattened onto
//                           it (obstacle.vert), in its colour without that light
#include "lighting.glsl"
#ifdef GROUND
#include "background.glsl"
#endif

in vec3 v_position;
in vec3 v_normal;

out vec4 frag_color;

#ifdef PLANE

flat in vec3 v_front_lit;
flat in vec3 v_front_shaded;
flat in vec3 v_back_lit;

uniform vec3 u_fade_center;   // world
uniform float u_fade_radius;  // m

// The key light reaches the ground, except under its shadow. The shadow falls on the
// ground's front, whichever way the flattened casters face.
#ifdef CAST_SHADOW
float key_visibility() { return 0.0; }
#define FRONT true
#else
float key_visibility() { return 1.0; }
#define FRONT gl_FrontFacing
#endif

#ifdef GROUND
// A plane obstacle in the ground (drawn before it, under it): its lit display colour, and 1
// when there is one (0 otherwise). Where the ground fades it shows through, fading too.
flat in vec3 v_under_lit;
uniform float u_under;
#endif

#if defined(GROUND) && defined(OPAQUE)
// Alpha is 1 here (r <= 0.45): nothing shows through, so no fade or background blend.
void main() {
  vec3 color = FRONT ? mix(v_front_shaded, v_front_lit, key_visibility()) : v_back_lit;
  frag_color = vec4(to_display(color), 1.0);
}
#else
void main() {
  vec3 color = FRONT ? mix(v_front_shaded, v_front_lit, key_visibility()) : v_back_lit;
  // Fades from r = 0.45 (the renderer's kGroundFadeStart) to 0.95.
  float r = length(v_position - u_fade_center) / u_fade_radius;
  float alpha = 1.0 - smoothstep(0.45, 0.95, r);
#ifdef GROUND
  // What blending the fading layers over the background would give, in one opaque write.
  vec3 behind = background_color();
  behind = mix(behind, to_display(v_under_lit), alpha * u_under);
  frag_color = vec4(mix(behind, to_display(color), alpha), 1.0);
#else
  frag_color = vec4(to_display(color), alpha);
#endif
}
#endif

#else

uniform vec3 u_albedo;  // linear

void main() {
  vec3 color = shade(u_albedo, normalize(v_normal), v_position, 48.0, 0.25, 1.0);
  frag_color = vec4(to_display(color), 1.0);
}

#endif
