// Meshes and cameras shared by the render tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>

#include <glm/glm.hpp>

#include <polder/camera.hpp>
#include <polder/grid_mesh.hpp>
#include <polder/image.hpp>
#include <polder/mesh_data.hpp>

namespace polder::test {

// A (cells+1)^2 grid over [-halfSize, halfSize]^2 around `origin`, heights from `height(x, y)`
// (local coordinates), triangles counter-clockwise seen from above. Normals are left empty
// when `withNormals` is false (the renderer then computes them).
inline MeshData makeGrid(const glm::dvec3& origin, float halfSize, int cells,
                         const std::function<float(float, float)>& height, bool withNormals = true) {
  MeshData mesh;
  mesh.origin = origin;
  const int n = cells + 1;
  const float step = 2.0f * halfSize / float(cells);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const float x = -halfSize + step * float(i), y = -halfSize + step * float(j);
      mesh.positions.emplace_back(x, y, height(x, y));
      if (withNormals) {
        // Central differences of the height function: the analytic normal of a smooth surface.
        const float e = 0.01f * step;
        const float dx = (height(x + e, y) - height(x - e, y)) / (2.0f * e);
        const float dy = (height(x, y + e) - height(x, y - e)) / (2.0f * e);
        mesh.normals.push_back(glm::normalize(glm::vec3(-dx, -dy, 1.0f)));
      }
    }
  }
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      const auto v00 = std::uint32_t(j * n + i), v10 = v00 + 1, v01 = v00 + std::uint32_t(n), v11 = v01 + 1;
      mesh.indices.insert(mesh.indices.end(), {v00, v10, v11, v00, v11, v01});
    }
  }
  return mesh;
}

// A grid mesh of samples [x0, x1] x [y0, y1] (inclusive, global sample coordinates) of the
// surface `height(metres east, metres north)`, anchored at its south-west sample.
struct GridMeshData {
  GridAnchor anchor;
  GridSpacing spacing;
  std::vector<GridMeshVertex> vertices;
  std::vector<std::uint32_t> indices;
  GridMeshView view() const { return GridMeshView{anchor, spacing, vertices, indices}; }
};

inline GridMeshData makeGridMesh(std::int64_t x0, std::int64_t y0, std::int64_t x1, std::int64_t y1,
                                 GridSpacing spacing, const std::function<float(double, double)>& height) {
  GridMeshData mesh;
  mesh.anchor = GridAnchor{x0, y0};
  mesh.spacing = spacing;
  const auto nx = std::uint32_t(x1 - x0 + 1), ny = std::uint32_t(y1 - y0 + 1);
  for (std::int64_t y = y0; y <= y1; ++y) {
    for (std::int64_t x = x0; x <= x1; ++x) {
      const double wx = double(x) * spacing.x, wy = double(y) * spacing.y;
      const double dx = (height(wx + spacing.x, wy) - height(wx - spacing.x, wy)) / (2.0 * spacing.x);
      const double dy = (height(wx, wy + spacing.y) - height(wx, wy - spacing.y)) / (2.0 * spacing.y);
      const glm::vec3 n = glm::normalize(glm::vec3(float(-dx), float(-dy), 1.0f));
      GridMeshVertex v;
      v.x = float(x - x0);
      v.y = float(y - y0);
      v.z = height(wx, wy);
      v.nx = snorm8(n.x), v.ny = snorm8(n.y), v.nz = snorm8(n.z);
      mesh.vertices.push_back(v);
    }
  }
  for (std::uint32_t j = 0; j + 1 < ny; ++j) {
    for (std::uint32_t i = 0; i + 1 < nx; ++i) {
      const std::uint32_t v00 = j * nx + i, v10 = v00 + 1, v01 = v00 + nx, v11 = v01 + 1;
      mesh.indices.insert(mesh.indices.end(), {v00, v10, v11, v00, v11, v01});
    }
  }
  return mesh;
}

inline float hills(float x, float y) {
  return 40.0f + 30.0f * std::sin(x * 0.021f) * std::cos(y * 0.017f) + 12.0f * std::sin((x + y) * 0.05f);
}

inline Camera smallCamera() {
  Camera camera;
  camera.widthPx = 128;
  camera.heightPx = 96;
  camera.fovYDeg = 60.0;
  return camera;
}

inline bool isTerrain(const RgbaImage& image, int x, int y) { return image.at(x, y)[3] == 255; }

inline int maxChannelDifference(const RgbaImage& a, const RgbaImage& b) {
  int worst = 0;
  if (a.pixels.size() != b.pixels.size()) return 256;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    worst = std::max(worst, std::abs(int(a.pixels[i]) - int(b.pixels[i])));
  }
  return worst;
}

inline std::uint8_t toByte(float c) { return std::uint8_t(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f)); }

}  // namespace polder::test
