// How terrain is shaded: one description used by the OpenGL renderer (shaders/terrain.frag
// mirrors shadeTerrain) and by the ray-cast reference renderer, so both draw the same picture.
#pragma once

#include <array>

#include <glm/glm.hpp>

namespace polder {

struct TerrainStyle {
  glm::vec3 sunDirection = glm::normalize(glm::vec3(-0.45f, 0.35f, 0.82f));  // towards the sun
  float ambient = 0.28f;
  // Elevation colour ramp: colours at 0, 1/4, 1/2, 3/4, 1 of [minHeightM, maxHeightM].
  std::array<glm::vec3, 5> ramp = {glm::vec3(0.20f, 0.38f, 0.22f), glm::vec3(0.42f, 0.55f, 0.28f),
                                   glm::vec3(0.62f, 0.56f, 0.38f), glm::vec3(0.55f, 0.50f, 0.47f),
                                   glm::vec3(0.96f, 0.96f, 0.97f)};
  float minHeightM = 0.0f;
  float maxHeightM = 1000.0f;
  glm::vec3 skyColour{0.62f, 0.74f, 0.88f};
  glm::vec3 fogColour{0.70f, 0.78f, 0.88f};
  float fogDensity = 0.0f;  // per metre; fog = 1 - exp(-(density * distance)^2)
  bool wireframe = false;   // overlay triangle edges
};

// Colour of a terrain point: elevation ramp, Lambert lighting with ambient, distance fog.
glm::vec3 shadeTerrain(const TerrainStyle& style, const glm::vec3& normal, float heightM, float distanceM);

// A fog density that leaves terrain at `distanceM` about half fogged.
float fogDensityForDistance(float distanceM);

}  // namespace polder
