#version 330 core
// Vertical gradient: the top pixel row is exactly u_top, the bottom row u_bottom.
#include "background.glsl"

out vec4 frag_color;

void main() {
  frag_color = vec4(background_color(), 1.0);
}
