#include <polder/terrain/full_resolution_mesh.hpp>

#include <algorithm>
#include <cassert>
#include <cstdint>

#include <polder/terrain/normals.hpp>

namespace polder::terrain {
namespace {

// Cells per chunk along one axis: as asked, but no more than kMaxChunkExtentM allows.
int cellsPerChunk(int chunkCells, double spacing) {
  const double fit = kMaxChunkExtentM / spacing;
  return fit >= double(chunkCells) ? chunkCells : std::max(1, int(fit));
}

MeshData buildChunk(const Heightfield& field, int x0, int y0, int x1, int y1) {
  MeshData mesh;
  mesh.origin = field.worldPosition(x0, y0);
  const int columns = x1 - x0 + 1, rows = y1 - y0 + 1;
  const std::size_t vertexCount = std::size_t(columns) * std::size_t(rows);
  mesh.positions.reserve(vertexCount);
  mesh.normals.reserve(vertexCount);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      // Offsets in whole samples times the spacing: exact in double, one rounding to float.
      mesh.positions.emplace_back(float((x - x0) * field.spacingX), float((y - y0) * field.spacingY),
                                  float(double(field.at(x, y)) - mesh.origin.z));
      mesh.normals.push_back(sampleNormal(field, x, y));
    }
  }
  mesh.indices.reserve(std::size_t(columns - 1) * std::size_t(rows - 1) * 6);
  for (int y = 0; y + 1 < rows; ++y) {
    for (int x = 0; x + 1 < columns; ++x) {
      const auto sw = std::uint32_t(y * columns + x), se = sw + 1;
      const auto nw = sw + std::uint32_t(columns), ne = nw + 1;
      // The diagonal runs from (x+1, y) to (x, y+1), as in heightfield.hpp and Embree's grids.
      mesh.indices.insert(mesh.indices.end(), {sw, se, nw, ne, nw, se});
    }
  }
  return mesh;
}

}  // namespace

std::vector<MeshData> buildFullResolutionMeshes(const Heightfield& field, int chunkCells) {
  assert(chunkCells >= 1 && chunkCells <= 65534 && "buildFullResolutionMeshes: chunkCells must be 1..65534");
  assert(field.heights.size() == field.sampleCount() && "buildFullResolutionMeshes: heights do not match the size");
  std::vector<MeshData> chunks;
  if (field.width < 2 || field.height < 2) return chunks;
  const int stepX = cellsPerChunk(chunkCells, field.spacingX), stepY = cellsPerChunk(chunkCells, field.spacingY);
  const int cellsX = field.width - 1, cellsY = field.height - 1;
  chunks.reserve(std::size_t((cellsX + stepX - 1) / stepX) * std::size_t((cellsY + stepY - 1) / stepY));
  for (int y0 = 0; y0 < cellsY; y0 += stepY)
    for (int x0 = 0; x0 < cellsX; x0 += stepX)
      chunks.push_back(buildChunk(field, x0, y0, std::min(x0 + stepX, cellsX), std::min(y0 + stepY, cellsY)));
  return chunks;
}

std::size_t fullResolutionTriangleCount(const Heightfield& field) {
  return fullResolutionTriangleCount(field.width, field.height);
}

std::size_t fullResolutionTriangleCount(int width, int height) {
  if (width < 2 || height < 2) return 0;
  return 2 * std::size_t(width - 1) * std::size_t(height - 1);
}

}  // namespace polder::terrain
