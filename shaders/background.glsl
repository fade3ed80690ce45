// The background gradient at this fragment (display colour), shared by the background
// pass and the ground, which blends into it at its fading edge.
uniform vec3 u_top;
uniform vec3 u_bottom;
uniform float u_height;  // image height in pixels

vec3 background_color() {
  float t = (gl_FragCoord.y - 0.5) / max(u_height - 1.0, 1.0);
  return mix(u_bottom, u_top, t);
}
