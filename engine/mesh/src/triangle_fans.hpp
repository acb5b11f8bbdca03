// Every vertex's triangles (its fan), for builders that walk fans in scattered order: a
// fan of up to kInline triangles lives in the vertex's own 64-byte record, so reaching it
// costs one cache miss rather than one for the list's header and one for its heap block.
// Longer fans (a representative that gathered much) spill to the heap. Fans keep the
// order triangles were added in.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace polder::mesh {

class TriangleFans {
 public:
  static constexpr std::uint32_t kInline = 15;

  // Each vertex's fan, from the triangles' corners (three per triangle), in triangle order.
  void build(std::size_t vertexCount, const std::vector<std::uint32_t>& corners) {
    clearAll(vertexCount);
    fill(corners, 0, static_cast<std::uint32_t>(vertexCount));
  }

  // Empty fans for `vertexCount` vertices.
  void clearAll(std::size_t vertexCount) {
    m_record.assign(vertexCount, Record{});
    m_spilled.assign(vertexCount, {});
  }

  // Adds the triangles to the fans of their corners in [begin, end), in triangle order;
  // threads may fill disjoint ranges at once.
  void fill(const std::vector<std::uint32_t>& corners, std::uint32_t begin, std::uint32_t end) {
    for (std::uint32_t t = 0; t < corners.size() / 3; ++t)
      for (int k = 0; k < 3; ++k)
        if (const std::uint32_t v = corners[3 * t + k]; v >= begin && v < end) push(v, t);
  }

  std::span<const std::uint32_t> operator[](std::uint32_t v) const {
    const Record& record = m_record[v];
    if (record.count <= kInline) return {record.triangles, record.count};
    return m_spilled[v];
  }

  // Starts loading v's record, for a walk that will reach it shortly.
  void prefetch(std::uint32_t v) const { __builtin_prefetch(&m_record[v]); }

  void push(std::uint32_t v, std::uint32_t t) {
    Record& record = m_record[v];
    if (record.count < kInline) {
      record.triangles[record.count++] = t;
      return;
    }
    std::vector<std::uint32_t>& spilled = m_spilled[v];
    if (record.count == kInline) spilled.assign(record.triangles, record.triangles + kInline);
    spilled.push_back(t);
    ++record.count;
  }

  // Removes the triangles for which `drop` holds, keeping the others' order.
  template <class Drop>
  void eraseIf(std::uint32_t v, const Drop& drop) {
    Record& record = m_record[v];
    if (record.count <= kInline) {
      record.count = static_cast<std::uint32_t>(
          std::remove_if(record.triangles, record.triangles + record.count, drop) - record.triangles);
      return;
    }
    std::vector<std::uint32_t>& spilled = m_spilled[v];
    std::erase_if(spilled, drop);
    record.count = static_cast<std::uint32_t>(spilled.size());
    if (record.count <= kInline) {
      std::copy(spilled.begin(), spilled.end(), record.triangles);
      std::vector<std::uint32_t>().swap(spilled);
    }
  }

  void erase(std::uint32_t v, std::uint32_t t) {
    eraseIf(v, [t](std::uint32_t u) { return u == t; });
  }

  // Removes t, moving the fan's last triangle into its place (order does not matter).
  void swapErase(std::uint32_t v, std::uint32_t t) {
    Record& record = m_record[v];
    std::uint32_t* begin = record.count <= kInline ? record.triangles : m_spilled[v].data();
    std::uint32_t* end = begin + record.count;
    std::uint32_t* at = std::find(begin, end, t);
    if (at == end) return;
    *at = end[-1];
    --record.count;
    if (record.count < kInline || begin == record.triangles) return;
    std::vector<std::uint32_t>& spilled = m_spilled[v];
    spilled.pop_back();
    if (record.count == kInline) {
      std::copy(spilled.begin(), spilled.end(), record.triangles);
      std::vector<std::uint32_t>().swap(spilled);
    }
  }

  void clear(std::uint32_t v) {
    Record& record = m_record[v];
    if (record.count > kInline) std::vector<std::uint32_t>().swap(m_spilled[v]);
    record.count = 0;
  }

 private:
  struct alignas(64) Record {
    std::uint32_t count = 0;
    std::uint32_t triangles[kInline];
  };
  std::vector<Record> m_record;
  std::vector<std::vector<std::uint32_t>> m_spilled;  // the whole fan, where count > kInline
};

}  // namespace polder::mesh
