#include "polder/mesh/progressive_mesh_instance.hpp"

#include <algorithm>
#include <array>
#include <tuple>

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
    state.borderTriangles.reserve(seq.foreignCorners().size());  // no allocation per frame
  }
}

void ProgressiveMeshInstance::setLevel(std::uint32_t region, std::uint32_t level) {
  const RegionSequence& seq = m_mesh->region(region);
  RegionState& state = m_regions[region];
  level = std::min(level, seq.levelCount());
  if (level == state.level) return;
  // The region's own moves can fold a pair of its border triangles too, and a flattened
  // pair's corners are set afresh once they move.
  if (!seq.foreignCorners().empty()) state.foldsUnchecked = true;
  if (state.hasFlattenedPair) state.bordersStale = true;
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
    if (state.bordersStale) {
      for (const ForeignCorner& corner : m_mesh->region(r).foreignCorners())
        state.indices[corner.slot] = m_regions[corner.region].borderTable[corner.entry];
      m_writes += m_mesh->region(r).foreignCorners().size();
      state.bordersStale = false;
      state.foldsUnchecked = true;
    }
    if (state.foldsUnchecked) flattenFoldedPairs(r);
    state.foldsUnchecked = false;
  }
}

// Whether the triangles holding the two slots have the same corners in the input (a
// double-sided sheet modelled so): the input's own, not a fold to flatten.
bool ProgressiveMeshInstance::backToBackInTheInput(std::uint32_t region, std::uint32_t slotX,
                                                   std::uint32_t slotY) const {
  const std::span<const std::uint32_t> full = m_mesh->region(region).fullIndices();
  auto corners = [&](std::uint32_t slot) {
    const std::uint32_t t = slot / 3;
    std::array<std::uint32_t, 3> c = {full[3 * t], full[3 * t + 1], full[3 * t + 2]};
    std::sort(c.begin(), c.end());
    return c;
  };
  return corners(slotX) == corners(slotY);
}

void ProgressiveMeshInstance::flattenFoldedPairs(std::uint32_t region) {
  RegionState& state = m_regions[region];
  const std::uint32_t drawnSlots = 3 * triangleCount(region);
  state.borderTriangles.clear();
  std::uint32_t lastTriangle = drawnSlots;  // no triangle
  for (const ForeignCorner& corner : m_mesh->region(region).foreignCorners()) {
    if (corner.slot >= drawnSlots) break;  // ascending slots
    const std::uint32_t t = corner.slot / 3, k = corner.slot % 3;
    if (t == lastTriangle) continue;  // a triangle with two foreign corners, once
    lastTriangle = t;
    const std::uint32_t c = state.indices[corner.slot];
    const std::uint32_t a = state.indices[3 * t + (k + 1) % 3], b = state.indices[3 * t + (k + 2) % 3];
    if (isDegenerate(a, b, c)) continue;
    state.borderTriangles.push_back({c, std::min(a, b), std::max(a, b), corner.slot, a < b});
  }
  auto key = [](const BorderTriangle& t) { return std::tie(t.foreign, t.lower, t.higher); };
  std::sort(state.borderTriangles.begin(), state.borderTriangles.end(),
            [&](const BorderTriangle& x, const BorderTriangle& y) { return key(x) < key(y); });
  state.hasFlattenedPair = false;
  const std::vector<BorderTriangle>& sorted = state.borderTriangles;
  for (std::size_t i = 0; i + 1 < sorted.size(); ++i) {
    const BorderTriangle &x = sorted[i], &y = sorted[i + 1];
    if (key(x) != key(y) || x.ascending == y.ascending || backToBackInTheInput(region, x.slot, y.slot)) continue;
    // Back to back: the foreign corner joins the lower corner, in both.
    state.indices[x.slot] = x.lower;
    state.indices[y.slot] = y.lower;
    m_writes += 2;
    state.hasFlattenedPair = true;
    ++i;
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

std::size_t ProgressiveMeshInstance::memoryBytes() const {
  std::size_t bytes = m_regions.capacity() * sizeof(RegionState);
  for (const RegionState& state : m_regions)
    bytes += state.indices.capacity() * sizeof(std::uint32_t) + state.borderTable.capacity() * sizeof(std::uint32_t) +
             state.borderTriangles.capacity() * sizeof(BorderTriangle);
  return bytes;
}

std::uint32_t ProgressiveMeshInstance::activeVertexCount(std::uint32_t region) const {
  return m_mesh->region(region).verticesAt(m_regions[region].level);
}

}  // namespace polder::mesh
