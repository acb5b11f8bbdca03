// Turning an instance's current levels into a standalone mesh (for files and measurement),
// and the edge bookkeeping used to check that simplification adds no open edges.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "polder/mesh/progressive_mesh_instance.hpp"
#include "polder/mesh/triangle_mesh.hpp"

namespace polder::mesh {

// The triangles the instance draws, over the vertices they use (compacted, attributes kept);
// flattened folds (degenerate, see resolveBorders) are left out.
TriangleMesh extractMesh(const ProgressiveMeshInstance& instance);

// The triangles with every vertex replaced by the first one at its bit-identical position:
// the surface's connectivity, with texture seams (vertices split where UVs differ) closed.
std::vector<std::uint32_t> indicesWeldedByPosition(const std::vector<std::uint32_t>& indices,
                                                   const std::vector<glm::vec3>& positions);

// Undirected edges used by exactly one triangle, each as (smaller, larger) vertex index.
std::vector<std::pair<std::uint32_t, std::uint32_t>> openEdges(const std::vector<std::uint32_t>& indices);

}  // namespace polder::mesh
