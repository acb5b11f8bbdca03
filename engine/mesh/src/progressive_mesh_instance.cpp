#include "polder/mesh/progressive_mesh_instance.hpp"

#include <algorithm>

namespace polder::mesh {

ProgressiveMeshInstance::ProgressiveMeshInstance(const ProgressiveMesh& mesh) : m_mesh(&mesh) {
  const std::uint32_t regionCount = mesh.regionCount();
  m_regions.resize(regionCount);
  for (std::uint32_t r = 0; r < regionCount; ++r) {
    const RegionSequence& seq = mesh.region(r);
    RegionState& state = m_regions[r];
    state.level = seq.levelCount();
    state.indices.assign(seq.fullIndices().begin(), seq.fullIndices().end());
    state.borderTable.assign(seq.borderVertices().begin(), seq.borderVertices().end());
  }
}

void ProgressiveMeshInstance::setLevel(std::uint32_t region, std::uint32_t level) {
  const RegionSequence& seq = m_mesh->region(region);
  RegionState& state = m_regions[region];
  level = std::min(level, seq.levelCount());
  if (level == state.level) return;
  const std::size_t stepCount = seq.levelCount();
  std::size_t tableWrites = 0;
  // Level l has taken steps [0, stepCount - l) from the original.
  if (level < state.level) {
    for (std::size_t step = stepCount - state.level; step < stepCount - level; ++step) {
      for (const CornerChange& c : seq.cornerChanges(step)) state.indices[c.slot] = c.after;
      for (const CornerChange& c : seq.borderChanges(step)) state.borderTable[c.slot] = c.after;
      m_writes += seq.cornerChanges(step).size();
      tableWrites += seq.borderChanges(step).size();
    }
  } else {
    for (std::size_t step = stepCount - state.level; step-- > stepCount - level;) {
      for (const CornerChange& c : seq.cornerChanges(step)) state.indices[c.slot] = c.before;
      for (const CornerChange& c : seq.borderChanges(step)) state.borderTable[c.slot] = c.before;
      m_writes += seq.cornerChanges(step).size();
      tableWrites += seq.borderChanges(step).size();
    }
  }
  m_writes += tableWrites;
  state.level = level;
  if (tableWrites > 0)
    for (std::uint32_t reader : seq.readers()) m_regions[reader].bordersStale = true;
}

void ProgressiveMeshInstance::resolveBorders() {
  for (std::uint32_t r = 0; r < m_regions.size(); ++r) {
    RegionState& state = m_regions[r];
    if (!state.bordersStale) continue;
    for (const ForeignCorner& corner : m_mesh->region(r).foreignCorners()) {
      state.indices[corner.slot] = m_regions[corner.region].borderTable[corner.entry];
    }
    m_writes += m_mesh->region(r).foreignCorners().size();
    state.bordersStale = false;
  }
}

std::span<const std::uint32_t> ProgressiveMeshInstance::indices(std::uint32_t region) const {
  return {m_regions[region].indices.data(), 3 * std::size_t(triangleCount(region))};
}

std::uint32_t ProgressiveMeshInstance::triangleCount(std::uint32_t region) const {
  return m_mesh->region(region).trianglesAt(m_regions[region].level);
}

std::uint64_t ProgressiveMeshInstance::triangleCount() const {
  std::uint64_t total = 0;
  for (std::uint32_t r = 0; r < m_regions.size(); ++r) total += triangleCount(r);
  return total;
}

std::uint32_t ProgressiveMeshInstance::activeVertexCount(std::uint32_t region) const {
  return m_mesh->region(region).verticesAt(m_regions[region].level);
}

}  // namespace polder::mesh
