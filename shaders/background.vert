#version 330 core
// Screen-space triangles (normalized device x, y) covering what the ground does not: at
// the far end of the depth range, drawn last with GL_LEQUAL, they fill only the samples
// that nothing else covered.
layout(location = 0) in vec2 a_position;

void main() {
  gl_Position = vec4(a_position, 1.0, 1.0);
}
