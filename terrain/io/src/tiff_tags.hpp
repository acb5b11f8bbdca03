// What libtiff tells about a TIFF that OpenImageIO 2.4 does not: the GeoTIFF tags, and
// whether the strips or tiles lie inside the file (OpenImageIO reads missing ones as zeros,
// without an error). Also declares the GeoTIFF tags on a TIFF being written. libtiff's
// types stay in the .cpp.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include <polder/result.hpp>
#include <polder/terrain/geotiff.hpp>

struct tiff;  // libtiff's TIFF

namespace polder::terrain::io {

// The tags of the first directory (empty ones when absent). Fails (InvalidData) when a
// strip or tile of that directory reaches past `fileLength`: a truncated file.
Result<GeoTiffTags> readTiffTags(const std::filesystem::path& path, std::uint64_t fileLength);

// Opens a TIFF with libtiff, its errors collected in `errors` instead of printed.
// `errors` must outlive the handle.
tiff* openTiff(const std::filesystem::path& path, const char* mode, std::string& errors);

// Declares ModelPixelScale, ModelTiepoint, GeoKeyDirectory and GDAL_NODATA on a TIFF
// being written, so TIFFSetField accepts them.
bool declareGeoTiffTags(tiff* file);

// The tags of Polder's float height TIFF (image_writer.hpp) on a TIFF being written: size,
// 32-bit float samples, deflate with the floating-point predictor, and the GeoTIFF tags of a
// local projected CRS in metres whose origin is the south-west sample. The layout (strips or
// tiles) is the caller's. False when libtiff refuses the GeoTIFF tags.
bool setHeightTiffTags(tiff* file, int width, int height, double spacingX, double spacingY);

}  // namespace polder::terrain::io
