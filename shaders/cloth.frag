#version 330 core
// Two-sided cloth: front and back colours, a fabric pattern laid out in rest (u, v)
// so stretch and shear show, and an optional anti-aliased wireframe.
#include "lighting.glsl"

in vec3 v_position;
in vec3 v_normal;
in vec2 v_rest_uv;
in vec3 v_barycentric;

uniform vec3 u_front_color;      // linear
uniform vec3 u_back_color;       // linear
uniform int u_pattern;           // 0 none, 1 weave, 2 checker
uniform float u_pattern_size;    // m of rest (u, v) per repeat
uniform int u_wireframe;         // 1 = draw triangle edges
uniform vec3 u_wireframe_color;  // display colour

out vec4 frag_color;

// Square wave of period 2 (+1 on [0, 1), -1 on [1, 2)) averaged over [x - w/2, x + w/2]:
// differences of its integral, the triangle wave 1 - |mod(x, 2) - 1|. No aliasing
// however small the pattern gets on screen.
float box_filtered_square(float x, float w) {
  w = max(w, 1e-4);
  float a = 1.0 - abs(mod(x + 0.5 * w, 2.0) - 1.0);
  float b = 1.0 - abs(mod(x - 0.5 * w, 2.0) - 1.0);
  return (a - b) / w;
}

// +1 / -1 squares of one unit in cell coordinates, filtered over the pixel footprint.
float filtered_checker(vec2 cell) {
  vec2 w = fwidth(cell);
  return box_filtered_square(cell.x, w.x) * box_filtered_square(cell.y, w.y);
}

// Relief of one thread crossing a cell: across the thread (a) a rounded profile with
// a dark gap at its sides, along it (b) a dip where it goes under the crossing thread.
float thread_relief(float a, float b) {
  float d = (2.0 * a - 1.0) / 0.88;
  float across = clamp(1.0 - d * d, 0.0, 1.0);
  float along = 0.8 + 0.2 * sin(3.14159265 * b);
  return mix(0.45, 1.0, sqrt(across) * along);
}

// Brightness factor of the pattern at rest coordinates uv (m).
float pattern_tone(vec2 uv) {
  if (u_pattern == 0) return 1.0;
  vec2 cell = 2.0 * uv / u_pattern_size;  // two threads / squares per repeat
  float checker = filtered_checker(cell);
  if (u_pattern == 2) return mix(0.62, 1.0, 0.5 + 0.5 * checker);
  // Plain weave: warp on top where the checker is +1, weft where it is -1, slightly
  // different tones; the thread relief fades to its mean when cells shrink below ~2 px.
  vec2 f = fract(cell);
  float warp_on_top = step(0.0, checker);
  float relief = mix(thread_relief(f.y, f.x), thread_relief(f.x, f.y), warp_on_top);
  float detail = 1.0 - smoothstep(0.3, 0.7, max(fwidth(cell).x, fwidth(cell).y));
  float tone = mix(0.80, 1.0, 0.5 + 0.5 * checker);
  return tone * mix(0.82, relief, detail);
}

void main() {
  vec3 n = normalize(v_normal);
  vec3 albedo = u_front_color;
  if (!gl_FrontFacing) {
    n = -n;
    albedo = u_back_color;
  }
  albedo *= pattern_tone(v_rest_uv);
  vec3 color = to_display(shade(albedo, n, v_position, 24.0, 0.08, 1.0));
  if (u_wireframe == 1) {
    // Distance to the nearest edge in pixels; about a 1 px line with soft sides.
    vec3 change = max(fwidth(v_barycentric), vec3(1e-6));
    vec3 pixels = v_barycentric / change;
    float edge = min(min(pixels.x, pixels.y), pixels.z);
    // Where triangles are only a few pixels across (far away, edge-on) the lines would
    // merge into a solid colour: fade them out there.
    float triangle_pixels = 1.0 / max(max(change.x, change.y), change.z);
    float line = (1.0 - smoothstep(0.5, 1.5, edge)) * smoothstep(2.0, 5.0, triangle_pixels);
    color = mix(color, u_wireframe_color, line);
  }
  frag_color = vec4(color, 1.0);
}
