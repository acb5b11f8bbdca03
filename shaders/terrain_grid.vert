#version 330 core
// Terrain pieces on the sample grid (polder/grid_mesh.hpp): a vertex is its offset from the
// piece's anchor in whole samples plus its height. Adding the piece's offset from the
// camera's anchor is exact in float, so a vertex shared by two pieces is the same three
// floats in both, and one matrix for every piece takes them to eye space bit-identically:
// neighbouring pieces meet without single-pixel holes.

layout(location = 0) in vec3 a_grid;    // x, y: samples from the piece's anchor; z: metres
layout(location = 1) in vec3 a_normal;  // unit, world frame (normalised from int8)

uniform vec2 u_gridOffset;  // piece anchor - camera anchor, whole samples
uniform mat4 u_gridToEye;   // spacing, the camera's remaining fraction, height and rotation
uniform mat4 u_projection;

out vec3 v_eye;      // eye-space position: fog uses its length (distance, not depth)
out vec3 v_normal;   // world frame
out float v_height;  // world z for the elevation ramp

void main() {
  vec4 eye = u_gridToEye * vec4(a_grid.xy + u_gridOffset, a_grid.z, 1.0);
  v_eye = eye.xyz;
  v_normal = a_normal;
  v_height = a_grid.z;
  gl_Position = u_projection * eye;
}
