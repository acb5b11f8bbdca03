// A regular grid of heights: the terrain every other part of Polder reads.
//
// Row 0 is the SOUTH edge (image files store the north edge first; readers flip), so
// sample (x, y) lies at world (x * spacingX, y * spacingY, height) in the frame of
// docs/design.md: x east, y north, z up, metres, origin at the south-west sample.
//
// Triangulation convention, shared by the renderer's full-resolution mesh and the Embree
// query scene (whose grid geometry splits each quad this way): the cell with corners
// (x, y) and (x+1, y+1) is cut along the diagonal from sample (x+1, y) to sample (x, y+1),
// into triangles {(x,y), (x+1,y), (x,y+1)} and {(x+1,y+1), (x,y+1), (x+1,y)}.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

namespace polder::terrain {

struct Heightfield {
  int width = 0;               // samples west to east
  int height = 0;              // samples south to north
  double spacingX = 1.0;       // metres between samples along x (east)
  double spacingY = 1.0;       // metres between samples along y (north)
  std::vector<float> heights;  // width * height metres, row-major, row 0 = south

  Heightfield() = default;
  Heightfield(int w, int h, double sx = 1.0, double sy = 1.0)
      : width(w), height(h), spacingX(sx), spacingY(sy), heights(std::size_t(w) * std::size_t(h), 0.0f) {}

  std::size_t sampleCount() const { return std::size_t(width) * std::size_t(height); }
  std::size_t index(int x, int y) const {
    assert(x >= 0 && x < width && y >= 0 && y < height && "Heightfield::index out of range");
    return std::size_t(y) * std::size_t(width) + std::size_t(x);
  }
  float at(int x, int y) const { return heights[index(x, y)]; }
  float& at(int x, int y) { return heights[index(x, y)]; }

  glm::dvec3 worldPosition(int x, int y) const { return {x * spacingX, y * spacingY, double(at(x, y))}; }
  double extentX() const { return (width - 1) * spacingX; }
  double extentY() const { return (height - 1) * spacingY; }
  // The lowest and highest sample (0, 0 for an empty field).
  std::pair<float, float> heightRange() const {
    if (heights.empty()) return {0.0f, 0.0f};
    const auto [low, high] = std::minmax_element(heights.begin(), heights.end());
    return {*low, *high};
  }
};

}  // namespace polder::terrain
