#include "polder/mesh/region_partition.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace polder::mesh {

namespace {

// Finer than any mesh needs, coarse enough that cell indices of three axes fit 64 bits.
constexpr std::uint32_t kMaxCellsPerAxis = 1u << 20;

// Cell index of every vertex for a grid of cellsPerAxis over b, then dense renumbering in
// cell order. Memory follows the vertices, not the cells: a grid far finer than the mesh
// costs no more than one cell per vertex.
RegionPartition partitionByCells(const std::vector<glm::vec3>& positions, const PositionBounds& b,
                                 const std::array<std::uint32_t, 3>& cellsPerAxis) {
  const glm::dvec3 extent = glm::max(b.hi - b.lo, glm::dvec3(1e-30));
  std::vector<std::uint64_t> cellOf(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    std::uint64_t cell = 0;
    for (int axis = 2; axis >= 0; --axis) {
      const double t = (double(positions[i][axis]) - b.lo[axis]) / extent[axis];
      const std::uint32_t n = std::clamp(cellsPerAxis[axis], 1u, kMaxCellsPerAxis);
      const auto c = std::min<std::uint32_t>(n - 1, static_cast<std::uint32_t>(std::clamp(t * n, 0.0, double(n))));
      cell = cell * n + c;
    }
    cellOf[i] = cell;
  }
  std::vector<std::uint64_t> occupied = cellOf;
  std::sort(occupied.begin(), occupied.end());
  occupied.erase(std::unique(occupied.begin(), occupied.end()), occupied.end());
  RegionPartition partition;
  partition.regionCount = std::max<std::uint32_t>(std::uint32_t(occupied.size()), 1u);
  partition.vertexRegion.resize(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i)
    partition.vertexRegion[i] =
        std::uint32_t(std::lower_bound(occupied.begin(), occupied.end(), cellOf[i]) - occupied.begin());
  return partition;
}

}  // namespace

RegionPartition singleRegion() { return RegionPartition{}; }

RegionPartition gridPartition(const std::vector<glm::vec3>& positions, std::array<std::uint32_t, 3> cells) {
  const PositionBounds b = boundsOf(positions);
  // Axes by decreasing extent: cells[0] cuts the longest one.
  const glm::dvec3 extent = b.hi - b.lo;
  std::array<int, 3> order{0, 1, 2};
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return extent[x] > extent[y]; });
  std::array<std::uint32_t, 3> perAxis{1, 1, 1};
  for (int k = 0; k < 3; ++k) perAxis[order[k]] = std::max(1u, cells[k]);
  return partitionByCells(positions, b, perAxis);
}

RegionPartition automaticPartition(const std::vector<glm::vec3>& positions, std::uint32_t regionCount) {
  // No more regions than vertices can be non-empty.
  regionCount = std::uint32_t(std::min<std::size_t>(regionCount, positions.size()));
  if (regionCount <= 1) return singleRegion();
  const PositionBounds b = boundsOf(positions);
  const glm::dvec3 extent = glm::max(b.hi - b.lo, glm::dvec3(1e-30));
  const double longest = std::max(extent.x, std::max(extent.y, extent.z));
  // Shrink a cubic cell until enough cells hold vertices (a surface fills few of a volume's cells).
  double cell = longest / std::cbrt(double(regionCount));
  RegionPartition partition;
  for (int attempt = 0; attempt < 64; ++attempt) {
    std::array<std::uint32_t, 3> perAxis{};
    for (int axis = 0; axis < 3; ++axis)
      perAxis[axis] = static_cast<std::uint32_t>(std::clamp(std::ceil(extent[axis] / cell), 1.0, 4096.0));
    partition = partitionByCells(positions, b, perAxis);
    if (partition.regionCount >= regionCount) break;
    cell *= 0.9;
  }
  return partition;
}

Status validatePartition(const RegionPartition& partition, std::size_t vertexCount, const std::string& what) {
  if (partition.regionCount == 0) return makeError(ErrorKind::InvalidArgument, what + ": zero regions");
  if (partition.vertexRegion.empty()) return {};
  if (partition.vertexRegion.size() != vertexCount)
    return makeError(ErrorKind::InvalidArgument, what + ": " + std::to_string(partition.vertexRegion.size()) +
                                                     " region ids for " + std::to_string(vertexCount) + " vertices");
  for (std::size_t i = 0; i < vertexCount; ++i)
    if (partition.vertexRegion[i] >= partition.regionCount)
      return makeError(ErrorKind::InvalidArgument, what + ": vertex " + std::to_string(i) + " is in region " +
                                                       std::to_string(partition.vertexRegion[i]) + " of " +
                                                       std::to_string(partition.regionCount));
  return {};
}

}  // namespace polder::mesh
