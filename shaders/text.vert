#version 330 core
// Glyph quads in pixels (origin top left, y down).
layout(location = 0) in vec2 a_pixel;
layout(location = 1) in vec2 a_atlas_uv;

uniform vec2 u_viewport;  // image size in pixels
uniform vec2 u_offset;    // pixels, for the drop shadow

out vec2 v_atlas_uv;

void main() {
  vec2 p = (a_pixel + u_offset) / u_viewport;
  v_atlas_uv = a_atlas_uv;
  gl_Position = vec4(2.0 * p.x - 1.0, 1.0 - 2.0 * p.y, 0.0, 1.0);
}
