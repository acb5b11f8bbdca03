#version 330 core
// Mirrors polder::shadeTerrain (engine/src/terrain_style.cpp) step by step: the ray-cast
// reference renderer shades on the CPU with it and the two images are compared. Change both
// together.

in vec3 v_eye;
in vec3 v_normal;
in float v_height;

uniform vec3 u_ramp[5];
uniform float u_minHeight;
uniform float u_maxHeight;
uniform vec3 u_sunDirection;  // unit, towards the sun
uniform float u_ambient;
uniform vec3 u_fogColour;
uniform float u_fogDensity;
uniform vec3 u_tint;
uniform float u_shade;  // 1 for the surface, RendererOptions::wireframeBrightness for edges

out vec4 o_colour;

void main() {
  float range = max(u_maxHeight - u_minHeight, 1e-6);
  float t = clamp((v_height - u_minHeight) / range, 0.0, 1.0) * 4.0;
  int stop = min(int(t), 3);
  vec3 albedo = mix(u_ramp[stop], u_ramp[stop + 1], t - float(stop));
  float diffuse = max(dot(normalize(v_normal), u_sunDirection), 0.0);
  vec3 lit = albedo * (u_ambient + (1.0 - u_ambient) * diffuse);
  float fogAmount = u_fogDensity * length(v_eye);
  float fog = 1.0 - exp(-fogAmount * fogAmount);
  vec3 colour = mix(lit, u_fogColour, fog);
  // Alpha 1 marks terrain; the clear writes 0 for sky.
  o_colour = vec4(colour * u_tint * u_shade, 1.0);
}
