// Choosing levels for every region of a progressive-mesh instance.
#pragma once

#include <cstdint>
#include <span>

#include "polder/mesh/progressive_mesh.hpp"

namespace polder::mesh {

// Levels with at most `triangles` triangles in all, as fine as possible, every region at
// the same object-space error (the smallest error whose levels fit). With one region this
// is the finest level with at most `triangles`. When even the base meshes have more, every
// region gets level 0. levels.size() must equal regionCount().
void levelsForTriangleBudget(const ProgressiveMesh& mesh, std::uint64_t triangles, std::span<std::uint32_t> levels);

}  // namespace polder::mesh
