#include "polder/mesh/mesh_extraction.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <unordered_map>

#include <polder/mix_bits.hpp>

namespace polder::mesh {

TriangleMesh extractMesh(const ProgressiveMeshInstance& instance) {
  const TriangleMesh& source = instance.mesh().vertices();
  constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> compact(source.vertexCount(), kUnused);
  TriangleMesh out;
  for (std::uint32_t r = 0; r < instance.mesh().regionCount(); ++r) {
    const std::span<const std::uint32_t> indices = instance.indices(r);
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
      const std::uint32_t a = indices[t], b = indices[t + 1], c = indices[t + 2];
      if (isDegenerate(a, b, c)) continue;  // a flattened fold (resolveBorders)
      for (std::uint32_t v : {a, b, c}) {
        if (compact[v] == kUnused) {
          compact[v] = static_cast<std::uint32_t>(out.positions.size());
          out.positions.push_back(source.positions[v]);
          if (source.hasNormals()) out.normals.push_back(source.normals[v]);
          if (source.hasColours()) out.colours.push_back(source.colours[v]);
          if (source.hasUvs()) out.uvs.push_back(source.uvs[v]);
        }
        out.indices.push_back(compact[v]);
      }
    }
  }
  return out;
}

std::vector<std::uint32_t> indicesWeldedByPosition(const std::vector<std::uint32_t>& indices,
                                                   const std::vector<glm::vec3>& positions) {
  auto bitsOf = [&](std::uint32_t v) { return std::bit_cast<std::array<std::uint32_t, 3>>(positions[v]); };
  struct BitsHash {
    std::size_t operator()(const std::array<std::uint32_t, 3>& b) const {
      return std::size_t(mixBits((std::uint64_t(b[0]) << 32 | b[1]) ^ mixBits(b[2])));
    }
  };
  std::unordered_map<std::array<std::uint32_t, 3>, std::uint32_t, BitsHash> first;
  std::vector<std::uint32_t> welded;
  welded.reserve(indices.size());
  for (std::uint32_t v : indices) welded.push_back(first.try_emplace(bitsOf(v), v).first->second);
  return welded;
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> openEdges(const std::vector<std::uint32_t>& indices) {
  std::vector<std::uint64_t> edges;
  edges.reserve(indices.size());
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = indices[t + k], b = indices[t + (k + 1) % 3];
      edges.push_back(std::min(a, b) << 32 | std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> open;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) open.emplace_back(static_cast<std::uint32_t>(edges[i] >> 32), static_cast<std::uint32_t>(edges[i]));
    i = j;
  }
  return open;
}

}  // namespace polder::mesh
