#version 330 core
// Depth from the key light for the shadow map.
layout(location = 0) in vec3 a_position;
uniform mat4 u_light_matrix;
uniform mat4 u_model;

void main() {
  gl_Position = u_light_matrix * u_model * vec4(a_position, 1.0);
}
