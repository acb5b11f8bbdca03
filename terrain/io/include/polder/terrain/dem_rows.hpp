// A DEM file read a band of rows at a time (height_rows.hpp), for DEMs larger than memory.
//
// Formats and heights are readDem's (dem_reader.hpp), from the same options: only the rows
// asked for are read and converted, whatever the file's size (no 2^31-sample limit).
//   TIFF/GeoTIFF and OpenEXR, striped or tiled: a band of strips or tiles at a time, the last
//     band kept. Any order of calls is fast.
//   SRTM .hgt and raw: positioned reads of the rows. Any order is fast.
//   PNG (greyscale, or Terrain-RGB / Terrarium with the encoding given): decoded from the
//     top; reading north to south (decreasing y0) is fast, every band read above the last one
//     decodes from the top again.
//   8-bit RGB(A) images with HeightEncoding::Auto: detecting the encoding needs every pixel,
//     so they are read whole through readDem, when their heights need at most
//     kDemRowsWholeReadBytes (and options.memoryLimitBytes); larger ones fail (OutOfMemory)
//     asking for the encoding. streamed() tells which.
//
// Voids differ from readDem, which fills them from all their neighbours over the whole
// raster. Here a void is filled along its row, linearly between the nearest valid samples on
// either side (copied from the one side at a row's ends); a row without any valid sample is
// copied from the nearest row that has one (the southern one of two equally near; rows read
// only for this are read once more). So the heights depend on the file alone, never on how
// the calls split it into bands. Files read whole keep readDem's filling.
//
// info(): path, format, encoding and spacingAssumed as readDem gives them; voids counts the
// voids of the distinct rows read so far (all of them after a pass over every row; all of
// them from the start when read whole); minM and maxM are set only when read whole.
//
// Errors never assert or throw; every message names the file. Opening fails as readDem does
// on a missing, corrupt or truncated file (Io, InvalidData, Unsupported, InvalidArgument);
// readRows fails with InvalidArgument for rows outside the raster, InvalidData for a file
// cut short since it was opened, an unreadable band, a NaN or infinite height, or no valid
// sample in any row.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>

#include <polder/result.hpp>
#include <polder/terrain/dem.hpp>
#include <polder/terrain/height_rows.hpp>

namespace polder::terrain {

// The most bytes an image that cannot be read by rows may need to be read whole.
inline constexpr std::uint64_t kDemRowsWholeReadBytes = std::uint64_t(1) << 30;

class DemRows : public HeightRows {
 public:
  // Known once open: everything but the height range and (when streamed) the voids.
  virtual const DemInfo& info() const = 0;
  // True when the file is read by rows; false when it was read whole.
  virtual bool streamed() const = 0;
};

Result<std::unique_ptr<DemRows>> openDemRows(const std::filesystem::path& path, const DemOptions& options = {});

}  // namespace polder::terrain
