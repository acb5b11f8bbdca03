// Small generated meshes for the progressive-mesh tests.
#pragma once

#include <cmath>
#include <cstdint>

#include "polder/mesh/triangle_mesh.hpp"

namespace polder::test {

// A (n+1) x (n+1) height grid over [0,1]^2 with a bumpy surface (an open mesh).
inline mesh::TriangleMesh bumpyGrid(std::uint32_t n, float amplitude = 0.1f) {
  mesh::TriangleMesh m;
  for (std::uint32_t j = 0; j <= n; ++j)
    for (std::uint32_t i = 0; i <= n; ++i) {
      const float x = float(i) / float(n), y = float(j) / float(n);
      m.positions.emplace_back(x, y, amplitude * (std::sin(7.0f * x) * std::cos(5.0f * y) + 0.3f * std::sin(23.0f * x * y)));
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
  for (std::uint32_t s = 0; s < segments; ++s) m.indices.insert(m.indices.end(), {0u, ringVertex(1, s), ringVertex(1, s + 1)});
  for (std::uint32_t r = 1; r + 1 < rings; ++r)
    for (std::uint32_t s = 0; s < segments; ++s) {
      const std::uint32_t a = ringVertex(r, s), b = ringVertex(r, s + 1), c = ringVertex(r + 1, s), d = ringVertex(r + 1, s + 1);
      m.indices.insert(m.indices.end(), {a, c, d, a, d, b});
    }
  for (std::uint32_t s = 0; s < segments; ++s)
    m.indices.insert(m.indices.end(), {south, ringVertex(rings - 1, s + 1), ringVertex(rings - 1, s)});
  return m;
}

}  // namespace polder::test
