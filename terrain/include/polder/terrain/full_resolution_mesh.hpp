// The whole heightfield as triangles, every sample a vertex: the reference the LOD meshes are
// compared against, and what the renderer draws when asked for full resolution.
#pragma once

#include <cstddef>
#include <vector>

#include <polder/mesh_data.hpp>
#include <polder/terrain/heightfield.hpp>

namespace polder::terrain {

// Chunks never span more than this many metres along an axis, so that float positions
// relative to a chunk's origin stay within a few millimetres of the exact ones (a float's
// spacing is 2^-23 of the value: 7.8 mm at 65 km).
inline constexpr double kMaxChunkExtentM = 65536.0;

// Cuts the grid into chunks of chunkCells x chunkCells cells, row by row from the south-west
// (edge chunks smaller, never stretched; where chunkCells cells would span more than
// kMaxChunkExtentM, fewer per chunk). Each chunk's origin is the world position of its
// south-west sample, its positions are relative to that, its normals come from sampleNormal,
// and its triangles follow heightfield.hpp's diagonal convention, counter-clockwise seen
// from above. Neighbouring chunks repeat their shared row or column of samples. A field
// with fewer than 2 x 2 samples gives no chunks. chunkCells must be 1..65534 (asserted).
std::vector<MeshData> buildFullResolutionMeshes(const Heightfield& field, int chunkCells = 255);

// 2 * (width - 1) * (height - 1): the triangles buildFullResolutionMeshes makes.
std::size_t fullResolutionTriangleCount(const Heightfield& field);
// The same for a DEM of width x height samples known by its size alone (a pyramid's header).
std::size_t fullResolutionTriangleCount(int width, int height);

}  // namespace polder::terrain
