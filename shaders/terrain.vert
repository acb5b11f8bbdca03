#version 330 core
// Terrain vertices, camera-relative: a_position is a float offset from the draw's origin and
// u_modelView already holds (origin - camera) computed in double on the CPU, so no large
// coordinate ever reaches the GPU. u_linear is the draw's rotation and scale (identity for
// terrain), u_normalMatrix its inverse transpose.

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;

uniform mat4 u_modelView;
uniform mat4 u_projection;
uniform float u_originHeight;  // world z of the draw's origin
uniform mat3 u_linear;
uniform mat3 u_normalMatrix;

out vec3 v_eye;      // eye-space position: fog uses its length (distance, not depth)
out vec3 v_normal;   // world frame
out float v_height;  // world z for the elevation ramp

void main() {
  vec3 offset = u_linear * a_position;  // from the origin, world axes
  vec4 eye = u_modelView * vec4(offset, 1.0);
  v_eye = eye.xyz;
  v_normal = u_normalMatrix * a_normal;
  v_height = u_originHeight + offset.z;
  gl_Position = u_projection * eye;
}
