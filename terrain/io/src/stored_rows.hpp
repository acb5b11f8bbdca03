// A DEM file's stored samples read a band of rows at a time, as the file holds them: north row
// first, channels interleaved, in the file's byte order. The row reader (dem_rows.cpp) turns
// them into heights.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>

#include <OpenImageIO/imageio.h>

#include <polder/result.hpp>

namespace polder::terrain::io {

class StoredRows {
 public:
  virtual ~StoredRows() = default;
  // Rows [first, first + count), counted from the north, into `out` (count * row bytes).
  // The caller checks the range. Errors name the problem, not the file.
  virtual Status read(int first, int count, std::byte* out) = 0;
};

// A headerless file of `rows` rows of `rowBytes` each from its first byte (raw, SRTM .hgt),
// read with positioned reads: any row costs the same. Io when it cannot be opened.
Result<std::unique_ptr<StoredRows>> openFileRows(const std::filesystem::path& path, std::uint64_t rowBytes);

// The first `channels` channels of an open image, as `type`. Tiled images are read a band of
// tiles at a time and striped TIFFs a band of strips, the last band kept (the next rows are
// usually in it); other images by scanlines, which for PNG means decoding from the top again
// whenever a row above the last one read is asked for.
std::unique_ptr<StoredRows> imageRows(std::unique_ptr<OIIO::ImageInput> input, int channels, OIIO::TypeDesc type);

}  // namespace polder::terrain::io
