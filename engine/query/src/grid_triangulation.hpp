// The heightfield triangulation convention (terrain/heightfield.hpp) as lookups: which
// triangle lies under a point, and the two triangles of a cell. Shared by the query scene
// (closed-form heights, hit refinement) and the reference renderer (normal interpolation).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/glm.hpp>

namespace polder::query::detail {

using TriangleSamples = std::array<glm::ivec2, 3>;  // sample coordinates, counter-clockwise from above

// Cell (cx, cy) is cut along the diagonal from (cx+1, cy) to (cx, cy+1).
inline std::array<TriangleSamples, 2> cellTriangles(int cx, int cy) {
  return {TriangleSamples{glm::ivec2(cx, cy), glm::ivec2(cx + 1, cy), glm::ivec2(cx, cy + 1)},
          TriangleSamples{glm::ivec2(cx + 1, cy + 1), glm::ivec2(cx, cy + 1), glm::ivec2(cx + 1, cy)}};
}

struct GridTriangle {
  TriangleSamples samples;
  std::array<double, 3> weights;  // barycentric weights of the point, summing to 1
};

// The triangle under the point at sample coordinates (sx, sy) = (x / spacingX, y / spacingY)
// of a width x height grid (at least 2x2). Points outside are clamped to the border cells,
// so their weights extrapolate.
inline GridTriangle gridTriangleAt(int width, int height, double sx, double sy) {
  const int cx = std::clamp(int(std::floor(sx)), 0, width - 2);
  const int cy = std::clamp(int(std::floor(sy)), 0, height - 2);
  const double a = sx - cx;
  const double b = sy - cy;
  const auto triangles = cellTriangles(cx, cy);
  if (a + b <= 1.0) return {triangles[0], {1.0 - a - b, a, b}};
  return {triangles[1], {a + b - 1.0, 1.0 - a, 1.0 - b}};
}

}  // namespace polder::query::detail
