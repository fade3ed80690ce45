#version 330 core
// Cloth vertices. With WIREFRAME the corners arrive three per triangle (not shared), so
// the corner index gives barycentric coordinates for the edges; otherwise the vertices
// are shared and drawn with indices.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_rest_uv;

uniform mat4 u_view_projection;

out vec3 v_position;
out vec3 v_normal;
out vec2 v_rest_uv;
#ifdef WIREFRAME
out vec3 v_barycentric;
#endif

void main() {
#ifdef WIREFRAME
  int corner = gl_VertexID % 3;
  v_barycentric = vec3(corner == 0, corner == 1, corner == 2);
#endif
  v_position = a_position;
  v_normal = a_normal;
  v_rest_uv = a_rest_uv;
  gl_Position = u_view_projection * vec4(a_position, 1.0);
}
