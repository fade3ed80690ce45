#version 330 core
// Two-sided cloth: front and back colours, a fabric pattern laid out in rest (u, v)
// so stretch and shear show, and an optional anti-aliased wireframe.
// Variants (#defined by the renderer): PATTERN 0 none, 1 weave, 2 checker; WIREFRAME.
#include "lighting.glsl"

#ifndef PATTERN
#define PATTERN 1
#endif

in vec3 v_position;
in vec3 v_normal;
in vec2 v_rest_uv;
#ifdef WIREFRAME
in vec3 v_barycentric;
uniform vec3 u_wireframe_color;  // display colour
#endif

uniform vec3 u_front_color;      // linear
uniform vec3 u_back_color;       // linear
uniform float u_cells_per_m;     // 2 / pattern size: threads or squares per m of rest (u, v)

out vec4 frag_color;

// Square wave of period 2 (+1 on [0, 1), -1 on [1, 2)) averaged over [x - w/2, x + w/2]:
// differences of its integral, the triangle wave 1 - |mod(x, 2) - 1|. No aliasing
// however small the pattern gets on screen. w > 0.
float box_filtered_square(float x, float w) {
  float a = 1.0 - abs(mod(x + 0.5 * w, 2.0) - 1.0);
  float b = 1.0 - abs(mod(x - 0.5 * w, 2.0) - 1.0);
  return (a - b) / w;
}

// sin(pi b) for b in [0, 1], as a polynomial in q = b (1 - b): exact at 0, 1/2 and 1 and in
// its slope at the ends, within 0.003 elsewhere (sin() is a long polynomial on llvmpipe).
float sin_pi(float b) {
  float q = b * (1.0 - b);
  return q * (3.14159265 + (16.0 - 4.0 * 3.14159265) * q);
}

// Brightness factor of the pattern at rest coordinates uv (m).
float pattern_tone(vec2 uv) {
#if PATTERN == 0
  return 1.0;
#else
  vec2 cell = u_cells_per_m * uv;  // two threads / squares per repeat
  vec2 w = fwidth(cell);
  vec2 wc = max(w, vec2(1e-4));
  // +1 / -1 squares of one unit in cell coordinates, filtered over the pixel footprint.
  float checker = box_filtered_square(cell.x, wc.x) * box_filtered_square(cell.y, wc.y);
#if PATTERN == 2
  return mix(0.62, 1.0, 0.5 + 0.5 * checker);
#else
  // Plain weave: warp on top where the checker is +1, weft where it is -1, slightly
  // different tones. Relief of the thread on top: across it (a) a rounded profile with a
  // dark gap at its sides, along it (b) a dip where it goes under the crossing thread.
  // The relief fades to its mean when cells shrink below ~2 px.
  vec2 f = fract(cell);
  bool warp_on_top = checker >= 0.0;
  float a = warp_on_top ? f.x : f.y;
  float b = warp_on_top ? f.y : f.x;
  float d = (2.0 * a - 1.0) / 0.88;
  float across = clamp(1.0 - d * d, 0.0, 1.0);
  float along = 0.8 + 0.2 * sin_pi(b);
  float relief = mix(0.45, 1.0, sqrt(across) * along);
  float detail = 1.0 - smoothstep(0.3, 0.7, max(w.x, w.y));
  float tone = mix(0.80, 1.0, 0.5 + 0.5 * checker);
  return tone * mix(0.82, relief, detail);
#endif
#endif
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
#ifdef WIREFRAME
  // Distance to the nearest edge in pixels; about a 1 px line with soft sides.
  vec3 change = max(fwidth(v_barycentric), vec3(1e-6));
  vec3 pixels = v_barycentric / change;
  float edge = min(min(pixels.x, pixels.y), pixels.z);
  // Where triangles are only a few pixels across (far away, edge-on) the lines would
  // merge into a solid colour: fade them out there.
  float triangle_pixels = 1.0 / max(max(change.x, change.y), change.z);
  float line = (1.0 - smoothstep(0.5, 1.5, edge)) * smoothstep(2.0, 5.0, triangle_pixels);
  color = mix(color, u_wireframe_color, line);
#endif
  frag_color = vec4(color, 1.0);
}
