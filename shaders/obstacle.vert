#version 330 core
// Obstacles and the ground: unit shapes placed by a model matrix. Planes (PLANE) are
// matte and flat, so their lighting is the same everywhere on each side: it is worked
// out here per vertex, leaving the fragment shader only the shadow look-up.
#ifdef PLANE
#include "lighting.glsl"
#endif

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;

uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view_projection;

out vec3 v_position;
out vec3 v_normal;

#ifdef PLANE
uniform vec3 u_albedo;        // linear
flat out vec3 v_front_lit;     // front side in full light
flat out vec3 v_front_shaded;  // front side without the key light
flat out vec3 v_back_lit;      // back side
#endif
#ifdef RECEIVE_SHADOW
uniform mat4 u_light_matrix;  // world -> key light clip space (shadow map)
out vec4 v_light_clip;
#endif
#ifdef GROUND
uniform vec3 u_under_albedo;   // linear: a plane obstacle lying in the ground
flat out vec3 v_under_lit;
#endif

void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_position = world.xyz;
  v_normal = u_normal_matrix * a_normal;
#ifdef PLANE
  vec3 n = normalize(v_normal);
  v_front_lit = shade(u_albedo, n, world.xyz, 1.0, 0.0, 1.0);
  v_front_shaded = shade(u_albedo, n, world.xyz, 1.0, 0.0, 0.0);
  v_back_lit = shade(u_albedo, -n, world.xyz, 1.0, 0.0, 1.0);
#endif
#ifdef RECEIVE_SHADOW
  v_light_clip = u_light_matrix * world;
#endif
#ifdef GROUND
  v_under_lit = shade(u_under_albedo, n, world.xyz, 1.0, 0.0, 1.0);
#endif
  gl_Position = u_view_projection * world;
}
