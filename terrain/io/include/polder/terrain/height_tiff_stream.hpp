// A float height TIFF (image_writer.hpp: 32-bit float metres, deflate, GeoTIFF spacing) written
// a band of rows at a time, for rasters larger than memory. The file is tiled (kTileSize^2
// tiles, so that readers can fetch any window), BigTIFF when it could pass 4 GiB, and atomic
// (core::PartialFile): it appears under its name only when finish() succeeds, and a writer
// destroyed before that, or a process killed, leaves no file that opens as complete.
//
// Rows go north first, the order the file stores them: each call writes the next band going
// south. readDem and openDemRows read the file back with its spacing, no options needed.
#pragma once

#include <filesystem>
#include <memory>
#include <span>

#include <polder/result.hpp>

namespace polder::terrain {

class HeightTiffStream {
 public:
  static constexpr int kTileSize = 256;

  // Fails (InvalidArgument) on a size below 1 x 1 or beyond 2^31 - 1 per side, a spacing that
  // is not positive and finite; (Io) when the file cannot be created or the disk has less free
  // space than the raster's uncompressed size.
  static Result<std::unique_ptr<HeightTiffStream>> create(const std::filesystem::path& path, int width, int height,
                                                          double spacingX, double spacingY);
  virtual ~HeightTiffStream() = default;

  virtual int width() const = 0;
  virtual int height() const = 0;
  virtual int rowsWritten() const = 0;

  // The next `count` rows going south, north row first, count * width() heights. `count` is
  // kTileSize, or what remains for the last band. Fails (InvalidArgument) on another count or
  // a non-finite height, (Io) when the disk refuses; after a failure the writer takes nothing
  // more and its file is removed when it is destroyed.
  virtual Status writeRows(int count, std::span<const float> heights) = 0;

  // Completes the file and renames it into place, once every row is written.
  virtual Status finish() = 0;
};

}  // namespace polder::terrain
