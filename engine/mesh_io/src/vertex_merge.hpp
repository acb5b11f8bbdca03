// Merging vertices of a TriangleMesh: exact duplicates, or all vertices at one position.
#pragma once

#include <polder/mesh/triangle_mesh.hpp>

namespace polder::mesh_io::detail {

// Vertices whose position and attributes are all bit-identical become one, in order of first
// occurrence; indices are remapped and no triangle is dropped. Unreferenced vertices stay.
void joinIdenticalVertices(mesh::TriangleMesh& mesh);

// Vertices with bit-identical positions become one (first occurrence's normal and texture
// coordinate, colours averaged), or with keepUvSeams those with equal positions and texture
// coordinates; triangles that then repeat a vertex are dropped.
void weldPositions(mesh::TriangleMesh& mesh, bool keepUvSeams);

}  // namespace polder::mesh_io::detail
