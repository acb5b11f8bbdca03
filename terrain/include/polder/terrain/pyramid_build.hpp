// Preparing a terrain pyramid (pyramid.hpp) from a DEM read a band of rows at a time: what
// `polder prep` runs. Memory is O(width x (2^k + 2) x a few levels), whatever the height: the
// levels are made as the rows arrive (level L + 1 takes every other sample of every other row
// of level L), each node is finished as soon as its rows are in, and its tile is written then.
//
// Per cell of every level above 0: the exact height range of the full-resolution samples under
// it and its residual, a bound on |full resolution - level surface| over it: the smaller of the
// finer cells' residual plus the largest gap between level L - 1's samples and the level-L
// surface over the cell (the level L - 1 triangulation refines the level-L one because every
// cell is cut along the same diagonal) and the distance between the cell's range and its
// corners'. Per node: the exact height range of its full-resolution footprint; its cells'
// residuals, stored in its tile, and the largest of them; the error bounds of
// BlockLod::buildFromLevel over the tile with those residuals; and the dikes' bound,
// the exact height range of dikeBoundRegion (dike_errors.hpp) from the neighbours' ranges.
//
// Atomic: the file is written as `<out>.partial-<pid>` in the same folder, its magic last,
// synced, and renamed onto `out` only when complete; on any error the partial file is removed
// and nothing is left at `out`.
//
// The result does not depend on the thread count or on how the source splits its reads.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include <polder/result.hpp>
#include <polder/terrain/height_rows.hpp>

namespace polder::core {
class ThreadPool;
}

namespace polder::terrain {

struct PyramidBuildOptions {
  int k = 5;                            // blocks of 2^k + 1 samples (block_layout.hpp), 1..7
  core::ThreadPool* pool = nullptr;     // nodes of a row are built on it; null: the calling thread
  std::function<void(float)> progress;  // 0..1, on the calling thread
  std::string sourceName;               // recorded in the header (at most 1024 bytes kept)
};

struct PyramidBuildReport {
  std::uint64_t nodes = 0;
  std::uint64_t fileBytes = 0;
  float minHeight = 0.0f;
  float maxHeight = 0.0f;
};

// InvalidArgument for options out of range or a source smaller than 2 x 2; InvalidData for a
// non-finite height (naming the source and sample); Io (naming the file) when the output
// cannot be written or the disk lacks room for it; the source's own errors as they come.
Result<PyramidBuildReport> buildPyramid(HeightRows& source, const std::filesystem::path& out,
                                        const PyramidBuildOptions& options = {});

}  // namespace polder::terrain
