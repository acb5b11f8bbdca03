// Meshes on a heightfield's integer sample grid, and how they reach the rasteriser without
// cracks (docs/design.md, "Block lifetimes").
//
// A grid mesh's vertex holds its position in sample units relative to the mesh's anchor, an
// integer sample (x east, y north), plus its height in metres. Every coordinate of a terrain
// vertex is an integer number of samples, so in float the sum
//
//     (vertex.x + (anchor.x - cameraAnchor.x),  vertex.y + (anchor.y - cameraAnchor.y))
//
// is exact (all terms are integers below 2^24): a vertex shared by two meshes with different
// anchors becomes the same three floats in both. One shared matrix (gridToEye, below) then
// takes every mesh's vertices to eye space: the spacing, the camera's remaining fraction of a
// sample, its height and its rotation. The same floats through the same matrix give the same
// clip coordinates, so neighbouring meshes meet without single-pixel holes; and since only
// camera-relative differences reach float, terrain 10^7 m from the world origin draws as
// steadily as terrain near it.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include <polder/camera.hpp>

namespace polder {

// A heightfield sample, in global sample coordinates.
struct GridAnchor {
  std::int64_t x = 0;
  std::int64_t y = 0;
  friend bool operator==(const GridAnchor&, const GridAnchor&) = default;
};

// Metres from one sample to the next, east and north.
struct GridSpacing {
  double x = 1.0;
  double y = 1.0;
  friend bool operator==(const GridSpacing&, const GridSpacing&) = default;
};

// One vertex of a grid mesh: 16 bytes, the layout the GL renderer uploads as it is.
struct GridMeshVertex {
  float x = 0.0f;  // samples east of the mesh's anchor (an integer value)
  float y = 0.0f;  // samples north of the mesh's anchor (an integer value)
  float z = 0.0f;  // height, metres
  // Unit normal in the world frame, each component in [-1, 1] scaled to the int8 range.
  std::int8_t nx = 0;
  std::int8_t ny = 0;
  std::int8_t nz = 127;
  std::int8_t pad = 0;
};
static_assert(sizeof(GridMeshVertex) == 16);

inline std::int8_t snorm8(float value) {
  return std::int8_t(std::lround(std::fmax(-1.0f, std::fmin(1.0f, value)) * 127.0f));
}
inline glm::vec3 normalOf(const GridMeshVertex& v) { return glm::vec3(float(v.nx), float(v.ny), float(v.nz)) / 127.0f; }

// A non-owning view of a grid mesh: counter-clockwise triangles seen from above.
struct GridMeshView {
  GridAnchor anchor;
  GridSpacing spacing;
  std::span<const GridMeshVertex> vertices;
  std::span<const std::uint32_t> indices;

  std::size_t triangleCount() const { return indices.size() / 3; }
};

// The camera's position split into the grid sample at or south-west of it and what remains
// (metres, each horizontal component in [0, spacing)).
struct GridCamera {
  GridAnchor anchor;
  glm::dvec3 remainder{0.0};  // x, y within the sample; z the camera's height
};

inline GridCamera gridCameraOf(const glm::dvec3& position, const GridSpacing& spacing) {
  GridCamera camera;
  camera.anchor =
      GridAnchor{std::int64_t(std::floor(position.x / spacing.x)), std::int64_t(std::floor(position.y / spacing.y))};
  camera.remainder = glm::dvec3(position.x - double(camera.anchor.x) * spacing.x,
                                position.y - double(camera.anchor.y) * spacing.y, position.z);
  return camera;
}

// The offset to add to a mesh's vertex x and y (exact in float while it stays below 2^24).
inline glm::vec2 gridOffset(const GridAnchor& mesh, const GridCamera& camera) {
  return glm::vec2(float(mesh.x - camera.anchor.x), float(mesh.y - camera.anchor.y));
}

// The one matrix every grid mesh of a frame shares: (vertex + gridOffset, z) to eye space.
inline glm::dmat4 gridToEye(const Camera& camera, const GridCamera& grid, const GridSpacing& spacing) {
  glm::dmat4 toCamera(1.0);
  toCamera[0][0] = spacing.x;
  toCamera[1][1] = spacing.y;
  toCamera[3] = glm::dvec4(-grid.remainder.x, -grid.remainder.y, -grid.remainder.z, 1.0);
  return camera.viewRotation() * toCamera;
}

// A vertex's world position (double), for hosts that want metres.
inline glm::dvec3 worldPosition(const GridMeshView& mesh, const GridMeshVertex& v) {
  return glm::dvec3((double(mesh.anchor.x) + double(v.x)) * mesh.spacing.x,
                    (double(mesh.anchor.y) + double(v.y)) * mesh.spacing.y, double(v.z));
}

}  // namespace polder
