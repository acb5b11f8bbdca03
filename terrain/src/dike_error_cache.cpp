#include <polder/terrain/dike_error_cache.hpp>

#include <algorithm>
#include <bit>

#include <polder/mix_bits.hpp>
#include <polder/terrain/dike_errors.hpp>

namespace polder::terrain {

namespace {

std::uint64_t key(const DikeVertex& v) { return (std::uint64_t(std::uint32_t(v.x)) << 32) | std::uint32_t(v.y); }

bool same(const DikeErrorCache::Triangle& t, const DikeVertex& a, const DikeVertex& b, const DikeVertex& c) {
  return t.v[0] == a && t.v[1] == b && t.v[2] == c;
}

// How far around the expected place the walk looks for a triangle of the last pass: a block
// whose mesh changed shifts the dike triangles after it by the few it gained or lost.
constexpr std::size_t kWindowBehind = 8;
constexpr std::size_t kWindowAhead = 24;

}  // namespace

float ExactDikeError::error(const DikeVertex& a, const DikeVertex& b, const DikeVertex& c,
                            const DikeTriangleRef&) const {
  return dikeTriangleError(m_field, a, b, c);
}

void DikeErrorCache::beginPass(std::size_t triangles) {
  std::swap(m_previous, m_current);
  m_current.clear();
  m_cursor = 0;
  if (m_current.capacity() < triangles) m_current.reserve(triangles);
  reserveTable(triangles);
}

void DikeErrorCache::reserveTable(std::size_t triangles) {
  const std::size_t size = std::bit_ceil(std::max<std::size_t>(4 * triangles, 1024));
  if (size > m_entries.size()) {
    m_entries.assign(size, Entry{});
    m_used = 0;
  }
}

const DikeErrorCache::Triangle& DikeErrorCache::lookUp(const DikeVertex& a, const DikeVertex& b, const DikeVertex& c,
                                                       const DikeTriangleRef& where) {
  const std::size_t lo = m_cursor > kWindowBehind ? m_cursor - kWindowBehind : 0;
  const std::size_t hi = std::min(m_previous.size(), m_cursor + kWindowAhead);
  std::size_t found = m_previous.size();
  if (m_cursor < m_previous.size() && same(m_previous[m_cursor], a, b, c)) {
    found = m_cursor;
  } else {
    for (std::size_t i = lo; i < hi; ++i)
      if (same(m_previous[i], a, b, c)) {
        found = i;
        break;
      }
  }
  if (found < m_previous.size()) {
    m_cursor = found + 1;
    m_current.push_back(m_previous[found]);
    return m_current.back();
  }
  const float za = m_measure.height(a, where.vertices[0]), zb = m_measure.height(b, where.vertices[1]),
              zc = m_measure.height(c, where.vertices[2]);
  m_current.push_back(
      Triangle{{a, b, c}, rememberedError(a, b, c, where), std::min({za, zb, zc}), std::max({za, zb, zc})});
  return m_current.back();
}

float DikeErrorCache::rememberedError(const DikeVertex& a, const DikeVertex& b, const DikeVertex& c,
                                      const DikeTriangleRef& where) {
  if (m_entries.empty()) reserveTable(0);
  // One key per triangle whatever vertex it starts at: the least vertex first (the winding,
  // counter-clockwise for every dike triangle, is kept).
  DikeVertex v[3] = {a, b, c};
  const auto less = [](const DikeVertex& p, const DikeVertex& q) { return p.x != q.x ? p.x < q.x : p.y < q.y; };
  if (less(v[1], v[0]) && less(v[1], v[2]))
    std::rotate(v, v + 1, v + 3);
  else if (less(v[2], v[0]) && less(v[2], v[1]))
    std::rotate(v, v + 2, v + 3);
  const std::size_t mask = m_entries.size() - 1;
  const std::size_t home = mixBits(mixBits(mixBits(key(v[0])) ^ key(v[1])) ^ key(v[2])) & mask;
  std::size_t slot = home;
  while (m_entries[slot].error >= 0.0f) {
    const Entry& entry = m_entries[slot];
    if (entry.v[0] == v[0] && entry.v[1] == v[1] && entry.v[2] == v[2]) return entry.error;
    slot = (slot + 1) & mask;
  }
  const float error = m_measure.error(a, b, c, where);
  if (2 * (m_used + 1) > m_entries.size()) {  // half full: forget, keep the memory
    std::fill(m_entries.begin(), m_entries.end(), Entry{});
    m_used = 0;
    slot = home;
  }
  m_entries[slot] = Entry{{v[0], v[1], v[2]}, error};
  ++m_used;
  return error;
}

}  // namespace polder::terrain
