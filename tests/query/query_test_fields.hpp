// Surfaces the query tests build, and the triangulation convention (heightfield_surface.hpp)
// to check the scene against.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include <polder/mesh_data.hpp>
#include <polder/terrain/heightfield.hpp>

#include "heightfield_surface.hpp"

namespace polder::query::test {

// A field whose sample (x, y) holds f(x * spacingX, y * spacingY).
template <class F>
terrain::Heightfield makeField(int width, int height, double spacingX, double spacingY, F f) {
  terrain::Heightfield field(width, height, spacingX, spacingY);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) field.at(x, y) = float(f(x * spacingX, y * spacingY));
  }
  return field;
}

using polder::test::conventionHeight;

// The field as a triangle mesh following the convention, positions relative to `origin`.
inline MeshData meshOfField(const terrain::Heightfield& field, const glm::dvec3& origin) {
  MeshData mesh;
  mesh.origin = origin;
  for (int y = 0; y < field.height; ++y) {
    for (int x = 0; x < field.width; ++x) mesh.positions.push_back(glm::vec3(field.worldPosition(x, y) - origin));
  }
  const auto id = [&](int x, int y) { return std::uint32_t(y * field.width + x); };
  for (int y = 0; y + 1 < field.height; ++y) {
    for (int x = 0; x + 1 < field.width; ++x) {
      mesh.indices.insert(mesh.indices.end(), {id(x, y), id(x + 1, y), id(x, y + 1)});
      mesh.indices.insert(mesh.indices.end(), {id(x + 1, y + 1), id(x, y + 1), id(x + 1, y)});
    }
  }
  return mesh;
}

inline double sinusoid(double x, double y) { return 20.0 * std::sin(0.3 * x) * std::cos(0.2 * y) + 3.0; }

}  // namespace polder::query::test
