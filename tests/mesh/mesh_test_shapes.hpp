// Small generated meshes for the progressive-mesh tests.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "polder/mesh/triangle_mesh.hpp"

namespace polder::test {

// A (n+1) x (n+1) height grid over [0,1]^2 with a bumpy surface (an open mesh).
inline mesh::TriangleMesh bumpyGrid(std::uint32_t n, float amplitude = 0.1f) {
  mesh::TriangleMesh m;
  for (std::uint32_t j = 0; j <= n; ++j)
    for (std::uint32_t i = 0; i <= n; ++i) {
      const float x = float(i) / float(n), y = float(j) / float(n);
      m.positions.emplace_back(x, y,
                               amplitude * (std::sin(7.0f * x) * std::cos(5.0f * y) + 0.3f * std::sin(23.0f * x * y)));
    }
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
    }
  return m;
}

// A closed, bumpy UV sphere (poles are single vertices).
inline mesh::TriangleMesh bumpySphere(std::uint32_t rings, std::uint32_t segments) {
  mesh::TriangleMesh m;
  const float pi = 3.14159265358979f;
  m.positions.emplace_back(0.0f, 0.0f, 1.0f);
  for (std::uint32_t r = 1; r < rings; ++r) {
    const float theta = pi * float(r) / float(rings);
    for (std::uint32_t s = 0; s < segments; ++s) {
      const float phi = 2.0f * pi * float(s) / float(segments);
      const float radius = 1.0f + 0.08f * std::sin(5.0f * phi) * std::sin(3.0f * theta);
      m.positions.emplace_back(radius * std::sin(theta) * std::cos(phi), radius * std::sin(theta) * std::sin(phi),
                               radius * std::cos(theta));
    }
  }
  m.positions.emplace_back(0.0f, 0.0f, -1.0f);
  const std::uint32_t south = static_cast<std::uint32_t>(m.positions.size() - 1);
  auto ringVertex = [&](std::uint32_t r, std::uint32_t s) { return 1 + (r - 1) * segments + s % segments; };
  for (std::uint32_t s = 0; s < segments; ++s)
    m.indices.insert(m.indices.end(), {0u, ringVertex(1, s), ringVertex(1, s + 1)});
  for (std::uint32_t r = 1; r + 1 < rings; ++r)
    for (std::uint32_t s = 0; s < segments; ++s) {
      const std::uint32_t a = ringVertex(r, s), b = ringVertex(r, s + 1), c = ringVertex(r + 1, s),
                          d = ringVertex(r + 1, s + 1);
      m.indices.insert(m.indices.end(), {a, c, d, a, d, b});
    }
  for (std::uint32_t s = 0; s < segments; ++s)
    m.indices.insert(m.indices.end(), {south, ringVertex(rings - 1, s + 1), ringVertex(rings - 1, s)});
  return m;
}

// bumpySphere with texture coordinates (u around, v down from the north pole) and a seam
// where u wraps: the vertices at phi = 0 come twice, u = 0 for the triangles east of the
// seam and u = 1 for those west of it. The poles, where the seam ends, come once.
inline mesh::TriangleMesh seamedSphere(std::uint32_t rings, std::uint32_t segments) {
  mesh::TriangleMesh m = bumpySphere(rings, segments);
  const auto original = static_cast<std::uint32_t>(m.vertexCount());
  const std::uint32_t south = original - 1;
  m.uvs.resize(original);
  m.uvs[0] = {0.5f, 0.0f};
  m.uvs[south] = {0.5f, 1.0f};
  for (std::uint32_t r = 1; r < rings; ++r)
    for (std::uint32_t s = 0; s < segments; ++s)
      m.uvs[1 + (r - 1) * segments + s] = {float(s) / float(segments), float(r) / float(rings)};
  // The west copies of the seam vertices, and the westernmost triangles moved onto them.
  std::vector<std::uint32_t> westCopy(original, 0);
  for (std::uint32_t r = 1; r < rings; ++r) {
    const std::uint32_t v = 1 + (r - 1) * segments;
    westCopy[v] = static_cast<std::uint32_t>(m.vertexCount());
    m.positions.push_back(m.positions[v]);
    m.uvs.push_back({1.0f, m.uvs[v].y});
  }
  for (std::size_t t = 0; t < m.triangleCount(); ++t) {
    bool west = false;  // a corner in the last segment
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = m.indices[3 * t + k];
      west |= v != 0 && v != south && (v - 1) % segments == segments - 1;
    }
    if (!west) continue;
    for (int k = 0; k < 3; ++k)
      if (const std::uint32_t v = m.indices[3 * t + k]; westCopy[v] != 0) m.indices[3 * t + k] = westCopy[v];
  }
  return m;
}

}  // namespace polder::test
