#include "vertex_merge.hpp"

#include <array>
#include <bit>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <polder/mix_bits.hpp>

namespace polder::mesh_io::detail {
namespace {

template <std::size_t N>
using Key = std::array<std::uint32_t, N>;

struct KeyHash {
  template <std::size_t N>
  std::size_t operator()(const Key<N>& key) const {
    std::uint64_t hash = N;
    for (std::uint32_t word : key) hash = mixBits(hash ^ (std::uint64_t(word) + 0x9e3779b97f4a7c15ull));
    return std::size_t(hash);
  }
};

template <std::size_t N>
void put(Key<N>& key, std::size_t& at, float value) {
  key[at++] = std::bit_cast<std::uint32_t>(value);
}

// The new index of every vertex: equal keys share one, numbered in order of first occurrence.
template <std::size_t N, class MakeKey>
std::vector<std::uint32_t> groupByKey(std::size_t vertexCount, MakeKey makeKey, std::uint32_t& groupCount) {
  std::unordered_map<Key<N>, std::uint32_t, KeyHash> groups;
  groups.reserve(vertexCount);
  std::vector<std::uint32_t> remap(vertexCount);
  for (std::size_t i = 0; i < vertexCount; ++i)
    remap[i] = groups.try_emplace(makeKey(i), std::uint32_t(groups.size())).first->second;
  groupCount = std::uint32_t(groups.size());
  return remap;
}

// Rebuilds the mesh with one vertex per group: the first member's attributes, colours
// optionally averaged over the members.
void applyGroups(mesh::TriangleMesh& mesh, const std::vector<std::uint32_t>& remap, std::uint32_t groupCount,
                 bool averageColours) {
  mesh::TriangleMesh merged;
  merged.positions.resize(groupCount);
  if (mesh.hasNormals()) merged.normals.resize(groupCount);
  if (mesh.hasUvs()) merged.uvs.resize(groupCount);
  if (mesh.hasColours()) merged.colours.resize(groupCount);
  std::vector<glm::dvec4> colourSums(averageColours && mesh.hasColours() ? groupCount : 0, glm::dvec4(0.0));
  std::vector<std::uint32_t> members(groupCount, 0);
  for (std::size_t i = 0; i < remap.size(); ++i) {
    const std::uint32_t group = remap[i];
    if (members[group]++ == 0) {
      merged.positions[group] = mesh.positions[i];
      if (mesh.hasNormals()) merged.normals[group] = mesh.normals[i];
      if (mesh.hasUvs()) merged.uvs[group] = mesh.uvs[i];
      if (mesh.hasColours()) merged.colours[group] = mesh.colours[i];
    }
    if (!colourSums.empty()) colourSums[group] += glm::dvec4(mesh.colours[i]);
  }
  for (std::size_t group = 0; group < colourSums.size(); ++group)
    merged.colours[group] = glm::vec4(colourSums[group] / double(members[group]));
  merged.indices.reserve(mesh.indices.size());
  for (std::uint32_t index : mesh.indices) merged.indices.push_back(remap[index]);
  mesh = std::move(merged);
}

}  // namespace

void joinIdenticalVertices(mesh::TriangleMesh& mesh) {
  std::uint32_t groupCount = 0;
  const auto remap = groupByKey<12>(
      mesh.vertexCount(),
      [&](std::size_t i) {
        Key<12> key{};
        std::size_t at = 0;
        for (int k = 0; k < 3; ++k) put(key, at, mesh.positions[i][k]);
        for (int k = 0; k < 3; ++k) put(key, at, mesh.hasNormals() ? mesh.normals[i][k] : 0.0f);
        for (int k = 0; k < 4; ++k) put(key, at, mesh.hasColours() ? mesh.colours[i][k] : 0.0f);
        for (int k = 0; k < 2; ++k) put(key, at, mesh.hasUvs() ? mesh.uvs[i][k] : 0.0f);
        return key;
      },
      groupCount);
  if (groupCount != mesh.vertexCount()) applyGroups(mesh, remap, groupCount, false);
}

void weldPositions(mesh::TriangleMesh& mesh, bool keepUvSeams) {
  std::uint32_t groupCount = 0;
  const bool byUvs = keepUvSeams && mesh.hasUvs();
  const auto remap = groupByKey<5>(
      mesh.vertexCount(),
      [&](std::size_t i) {
        Key<5> key{};
        std::size_t at = 0;
        for (int k = 0; k < 3; ++k) put(key, at, mesh.positions[i][k]);
        for (int k = 0; k < 2; ++k) put(key, at, byUvs ? mesh.uvs[i][k] : 0.0f);
        return key;
      },
      groupCount);
  if (groupCount != mesh.vertexCount()) applyGroups(mesh, remap, groupCount, true);
  // Drop triangles that repeat a vertex (welded, or already so in the file).
  std::size_t kept = 0;
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const std::uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
    if (mesh::isDegenerate(a, b, c)) continue;
    mesh.indices[kept++] = a;
    mesh.indices[kept++] = b;
    mesh.indices[kept++] = c;
  }
  mesh.indices.resize(kept);
}

}  // namespace polder::mesh_io::detail
