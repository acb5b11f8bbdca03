#version 330 core
// Terrain vertices, camera-relative: a_position is a float offset from the draw's origin and
// u_modelView already holds (origin - camera) computed in double on the CPU, so no large
// coordinate ever reaches the GPU.

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;

uniform mat4 u_modelView;
uniform mat4 u_projection;
uniform float u_originHeight;  // world z of the draw's origin

out vec3 v_eye;      // eye-space position: fog uses its length (distance, not depth)
out vec3 v_normal;   // world frame; the model transform is a pure translation
out float v_height;  // world z for the elevation ramp

void main() {
  vec4 eye = u_modelView * vec4(a_position, 1.0);
  v_eye = eye.xyz;
  v_normal = a_normal;
  v_height = u_originHeight + a_position.z;
  gl_Position = u_projection * eye;
}
