#version 330 core
// Obstacles and the ground: unit shapes placed by a model matrix. Planes (PLANE) are
// matte and flat, so their lighting is the same everywhere on each side: it is worked
// out here per vertex, leaving the fragment shader only the fade. With CAST_SHADOW the
// casters are drawn flattened onto the ground: their shadow on it.
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
#ifdef GROUND
uniform vec3 u_under_albedo;   // linear: a plane obstacle lying in the ground
flat out vec3 v_under_lit;
#endif

#ifdef CAST_SHADOW
// The casters flattened onto the ground along the key light: their shadow, as geometry.
uniform mat4 u_shadow_projection;  // world -> the ground plane, along the key light
uniform float u_ground_height;     // m
uniform vec4 u_ground_square;      // the ground's square: min x, min y, max x, max y (m)
#endif

void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
#ifdef CAST_SHADOW
  // Only what is above the ground casts onto it, and only onto its square.
  gl_ClipDistance[0] = world.z - u_ground_height;
  world = u_shadow_projection * world;
  gl_ClipDistance[1] = world.x - u_ground_square.x;
  gl_ClipDistance[2] = world.y - u_ground_square.y;
  gl_ClipDistance[3] = u_ground_square.z - world.x;
  gl_ClipDistance[4] = u_ground_square.w - world.y;
  v_normal = vec3(0.0, 0.0, 1.0);
#else
  v_normal = u_normal_matrix * a_normal;
#endif
  v_position = world.xyz;
#ifdef PLANE
  vec3 n = normalize(v_normal);
  v_front_lit = shade(u_albedo, n, world.xyz, 1.0, 0.0, 1.0);
  v_front_shaded = shade(u_albedo, n, world.xyz, 1.0, 0.0, 0.0);
  v_back_lit = shade(u_albedo, -n, world.xyz, 1.0, 0.0, 1.0);
#endif
#ifdef GROUND
  v_under_lit = shade(u_under_albedo, n, world.xyz, 1.0, 0.0, 1.0);
#endif
  gl_Position = u_view_projection * world;
}
