#include <polder/terrain_style.hpp>

#include <algorithm>
#include <cmath>

namespace polder {

glm::vec3 shadeTerrain(const TerrainStyle& style, const glm::vec3& normal, float heightM, float distanceM) {
  const float range = std::max(style.maxHeightM - style.minHeightM, 1e-6f);
  const float t = std::clamp((heightM - style.minHeightM) / range, 0.0f, 1.0f) * 4.0f;
  const int stop = std::min(int(t), 3);
  const glm::vec3 albedo = glm::mix(style.ramp[std::size_t(stop)], style.ramp[std::size_t(stop) + 1], t - float(stop));
  const float diffuse = std::max(glm::dot(glm::normalize(normal), style.sunDirection), 0.0f);
  const glm::vec3 lit = albedo * (style.ambient + (1.0f - style.ambient) * diffuse);
  const float fogAmount = style.fogDensity * distanceM;
  const float fog = 1.0f - std::exp(-fogAmount * fogAmount);
  return glm::mix(lit, style.fogColour, fog);
}

float fogDensityForDistance(float distanceM) {
  // 1 - exp(-(d * D)^2) = 0.5  =>  d = sqrt(ln 2) / D
  return std::sqrt(std::log(2.0f)) / std::max(distanceM, 1.0f);
}

}  // namespace polder
