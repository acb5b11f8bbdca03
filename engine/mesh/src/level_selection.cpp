#include "polder/mesh/level_selection.hpp"

#include <algorithm>
#include <cassert>

namespace polder::mesh {

namespace {

std::uint64_t trianglesAtError(const ProgressiveMesh& mesh, float error, std::span<std::uint32_t> levels) {
  std::uint64_t total = 0;
  for (std::uint32_t r = 0; r < mesh.regionCount(); ++r) {
    levels[r] = mesh.region(r).levelForError(error);
    total += mesh.region(r).trianglesAt(levels[r]);
  }
  return total;
}

}  // namespace

void levelsForTriangleBudget(const ProgressiveMesh& mesh, std::uint64_t triangles, std::span<std::uint32_t> levels) {
  assert(levels.size() == mesh.regionCount());
  if (mesh.regionCount() == 1) {
    levels[0] = mesh.region(0).levelForTriangles(static_cast<std::uint32_t>(std::min<std::uint64_t>(triangles, ~0u)));
    return;
  }
  // The triangle count falls as the error threshold grows: bisect on the threshold.
  float lo = 0.0f, hi = 0.0f;
  for (std::uint32_t r = 0; r < mesh.regionCount(); ++r) hi = std::max(hi, mesh.region(r).errorAt(0));
  if (trianglesAtError(mesh, lo, levels) <= triangles) return;
  for (int i = 0; i < 64 && lo < hi; ++i) {
    const float mid = 0.5f * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    if (trianglesAtError(mesh, mid, levels) <= triangles)
      hi = mid;
    else
      lo = mid;
  }
  trianglesAtError(mesh, hi, levels);
}

}  // namespace polder::mesh
