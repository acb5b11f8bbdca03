#include <polder/terrain/normals.hpp>

#include <algorithm>

namespace polder::terrain {

glm::vec3 sampleNormal(const Heightfield& field, int x, int y) {
  const int x0 = std::max(x - 1, 0), x1 = std::min(x + 1, field.width - 1);
  const int y0 = std::max(y - 1, 0), y1 = std::min(y + 1, field.height - 1);
  const double dzdx = x1 > x0 ? (double(field.at(x1, y)) - field.at(x0, y)) / ((x1 - x0) * field.spacingX) : 0.0;
  const double dzdy = y1 > y0 ? (double(field.at(x, y1)) - field.at(x, y0)) / ((y1 - y0) * field.spacingY) : 0.0;
  return glm::vec3(glm::normalize(glm::dvec3(-dzdx, -dzdy, 1.0)));
}

}  // namespace polder::terrain
