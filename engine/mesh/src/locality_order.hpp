// The builders visit a vertex's neighbours over and over. Scanned and zippered meshes
// number their vertices in no spatial order (on the Stanford bunny a sixth of the
// triangles span over 10,000 ids), so each visit misses the cache. Building on a copy
// whose vertices follow a Morton curve through the bounding box, and whose triangles
// follow their first vertex, keeps neighbours a few entries apart; the steps are then
// renamed back to the caller's vertex ids.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "polder/mesh/region_partition.hpp"
#include "polder/mesh/simplification_steps.hpp"
#include "polder/mesh/triangle_mesh.hpp"
#include "step_listener.hpp"

namespace polder::mesh {

struct LocalityOrdered {
  TriangleMesh mesh;                      // the input, vertices and triangles renumbered
  RegionPartition partition;              // the input's, per renumbered vertex
  std::vector<std::uint32_t> originalOf;  // renumbered vertex -> the input's id
};

namespace detail {

// Spreads the low 21 bits of x three apart (bit i goes to bit 3i).
inline std::uint64_t spreadBits3(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

// Sorts (key, id) pairs by key, equal keys in their current order: a least-significant-
// digit radix sort, 11 bits per pass (linear, where a comparison sort spent most of the
// ordering's time; six passes cover a 63-bit Morton code, and 2,048 counters stay in the
// first-level cache). Passes whose digit is the same for every key are skipped.
inline void radixSortByKey(std::vector<std::pair<std::uint64_t, std::uint32_t>>& items) {
  constexpr int kDigitBits = 11;
  constexpr std::uint64_t kDigitMask = (1u << kDigitBits) - 1;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> scratch(items.size());
  std::vector<std::uint32_t> start(kDigitMask + 2);
  for (int shift = 0; shift < 64; shift += kDigitBits) {
    std::fill(start.begin(), start.end(), 0u);
    for (const auto& item : items) ++start[((item.first >> shift) & kDigitMask) + 1];
    if (std::any_of(start.begin() + 1, start.end(), [&](std::uint32_t n) { return n == items.size(); })) continue;
    for (std::uint64_t b = 0; b <= kDigitMask; ++b) start[b + 1] += start[b];
    for (const auto& item : items) scratch[start[(item.first >> shift) & kDigitMask]++] = item;
    items.swap(scratch);
  }
}

}  // namespace detail

inline LocalityOrdered inLocalityOrder(const TriangleMesh& mesh, const RegionPartition& partition) {
  const auto vertexCount = static_cast<std::uint32_t>(mesh.vertexCount());
  const PositionBounds bounds = boundsOf(mesh.positions);
  const glm::dvec3 extent = bounds.hi - bounds.lo;
  const double scale = 2097151.0 / std::max({extent.x, extent.y, extent.z, 1e-300});
  std::vector<std::pair<std::uint64_t, std::uint32_t>> order(vertexCount);  // (Morton code, vertex)
  for (std::uint32_t v = 0; v < vertexCount; ++v) {
    const glm::dvec3 q = (glm::dvec3(mesh.positions[v]) - bounds.lo) * scale;
    const std::uint64_t code = detail::spreadBits3(std::uint64_t(q.x)) | detail::spreadBits3(std::uint64_t(q.y)) << 1 |
                               detail::spreadBits3(std::uint64_t(q.z)) << 2;
    order[v] = {code, v};
  }
  detail::radixSortByKey(order);  // ids ascend, so equal codes stay in id order
  // Vertices closer than the code's resolution: by position, then attributes, so the
  // input's numbering decides only between copies of one vertex.
  auto lexicographic = [](const auto& p, const auto& q) {
    for (int k = 0; k < p.length(); ++k)
      if (p[k] != q[k]) return p[k] < q[k] ? -1 : 1;
    return 0;
  };
  auto byContent = [&](const auto& a, const auto& b) {
    const std::uint32_t u = a.second, v = b.second;
    if (int c = lexicographic(mesh.positions[u], mesh.positions[v])) return c < 0;
    if (mesh.hasNormals())
      if (int c = lexicographic(mesh.normals[u], mesh.normals[v])) return c < 0;
    if (mesh.hasColours())
      if (int c = lexicographic(mesh.colours[u], mesh.colours[v])) return c < 0;
    if (mesh.hasUvs())
      if (int c = lexicographic(mesh.uvs[u], mesh.uvs[v])) return c < 0;
    return u < v;
  };
  for (auto run = order.begin(); run != order.end();) {
    const auto end = std::find_if(run, order.end(), [&](const auto& e) { return e.first != run->first; });
    if (end - run > 1) std::sort(run, end, byContent);
    run = end;
  }

  LocalityOrdered out;
  out.originalOf.resize(vertexCount);
  std::vector<std::uint32_t> renamed(vertexCount);
  for (std::uint32_t i = 0; i < vertexCount; ++i) {
    out.originalOf[i] = order[i].second;
    renamed[order[i].second] = i;
  }
  auto permute = [&](const auto& from, auto& to) {
    if (from.empty()) return;
    to.resize(vertexCount);
    for (std::uint32_t i = 0; i < vertexCount; ++i) to[i] = from[out.originalOf[i]];
  };
  permute(mesh.positions, out.mesh.positions);
  permute(mesh.normals, out.mesh.normals);
  permute(mesh.colours, out.mesh.colours);
  permute(mesh.uvs, out.mesh.uvs);
  out.partition.regionCount = partition.regionCount;
  permute(partition.vertexRegion, out.partition.vertexRegion);

  // Triangles by their corners, each turned to start at its smallest (the winding stays):
  // a counting sort on the first corner, then the few sharing it by the other two. With
  // the Morton order this makes the build independent of how the input numbers its
  // vertices and orders its triangles.
  const std::size_t triangleCount = mesh.triangleCount();
  std::vector<std::array<std::uint32_t, 3>> turned(triangleCount);
  std::vector<std::uint32_t> start(std::size_t(vertexCount) + 1, 0);
  for (std::size_t t = 0; t < triangleCount; ++t) {
    std::array<std::uint32_t, 3> c{renamed[mesh.indices[3 * t]], renamed[mesh.indices[3 * t + 1]],
                                   renamed[mesh.indices[3 * t + 2]]};
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    turned[t] = c;
    ++start[c[0] + 1];
  }
  for (std::uint32_t v = 0; v < vertexCount; ++v) start[v + 1] += start[v];
  std::vector<std::array<std::uint32_t, 3>> sorted(triangleCount);
  std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
  for (const auto& c : turned) sorted[next[c[0]]++] = c;
  for (std::uint32_t v = 0; v < vertexCount; ++v) std::sort(sorted.begin() + start[v], sorted.begin() + start[v + 1]);
  out.mesh.indices.resize(mesh.indices.size());
  for (std::size_t t = 0; t < triangleCount; ++t)
    for (int k = 0; k < 3; ++k) out.mesh.indices[3 * t + k] = sorted[t][k];
  return out;
}

// Runs build(mesh, partition) -> SimplificationSteps on the copy in locality order and
// renames the steps' vertices back to the input's ids; a listener learns the renaming first.
template <class Build>
SimplificationSteps buildInLocalityOrder(const TriangleMesh& mesh, const RegionPartition& partition,
                                         StepListener* listener, const Build& build) {
  const LocalityOrdered ordered = inLocalityOrder(mesh, partition);
  if (listener) listener->renumbered(ordered.originalOf);
  SimplificationSteps steps = build(ordered.mesh, ordered.partition);
  for (std::uint32_t& v : steps.representative) v = ordered.originalOf[v];
  for (std::uint32_t& v : steps.removed) v = ordered.originalOf[v];
  for (std::uint32_t& v : steps.onto) v = ordered.originalOf[v];
  return steps;
}

}  // namespace polder::mesh
