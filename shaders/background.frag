#version 330 core
// Vertical gradient: the top pixel row is exactly u_top, the bottom row u_bottom.
uniform vec3 u_top;
uniform vec3 u_bottom;
uniform float u_height;  // image height in pixels
out vec4 frag_color;

void main() {
  float t = (gl_FragCoord.y - 0.5) / max(u_height - 1.0, 1.0);
  frag_color = vec4(mix(u_bottom, u_top, t), 1.0);
}
