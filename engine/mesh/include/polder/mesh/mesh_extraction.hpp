// Turning an instance's current levels into a standalone mesh (for files and measurement),
// and the edge bookkeeping used to check that simplification adds no open edges.
#pragma once

#include <cstdint>
#include <vector>

#include "polder/mesh/progressive_mesh_instance.hpp"
#include "polder/mesh/triangle_mesh.hpp"

namespace polder::mesh {

// The triangles the instance draws, over the vertices they use (compacted, attributes kept).
TriangleMesh extractMesh(const ProgressiveMeshInstance& instance);

// Undirected edges used by exactly one triangle, each as (smaller, larger) vertex index.
std::vector<std::pair<std::uint32_t, std::uint32_t>> openEdges(const std::vector<std::uint32_t>& indices);

}  // namespace polder::mesh
