#version 330 core
// The atlas stores glyph coverage, which becomes the alpha of a flat colour.
in vec2 v_atlas_uv;

uniform sampler2D u_atlas;
uniform vec4 u_color;

out vec4 frag_color;

void main() {
  frag_color = vec4(u_color.rgb, u_color.a * texture(u_atlas, v_atlas_uv).r);
}
