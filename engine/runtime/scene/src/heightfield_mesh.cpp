#include "polder/scene/heightfield_mesh.hpp"

#include <cstdint>

namespace polder::scene {

mesh::TriangleMesh heightfieldMesh(const terrain::Heightfield& field) {
  mesh::TriangleMesh mesh;
  mesh.positions.reserve(std::size_t(field.width) * std::size_t(field.height));
  for (int j = 0; j < field.height; ++j)
    for (int i = 0; i < field.width; ++i)
      mesh.positions.emplace_back(float(i * field.spacingX), float(j * field.spacingY), field.at(i, j));
  if (field.width >= 2 && field.height >= 2)
    mesh.indices.reserve(6 * std::size_t(field.width - 1) * std::size_t(field.height - 1));
  for (int j = 0; j + 1 < field.height; ++j)
    for (int i = 0; i + 1 < field.width; ++i) {
      const auto a = std::uint32_t(j * field.width + i), b = a + 1, c = a + std::uint32_t(field.width), d = c + 1;
      mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
    }
  mesh.normals = mesh::computeVertexNormals(mesh.positions, mesh.indices);
  return mesh;
}

}  // namespace polder::scene
