// Reading PNG, TIFF/GeoTIFF and OpenEXR DEMs through OpenImageIO. The steps before the pixels
// (opening, choosing the channels, the file's hints) are shared with the row reader
// (dem_rows.cpp), so both turn a file into the same heights.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <OpenImageIO/imageio.h>

#include <polder/result.hpp>
#include <polder/terrain/dem.hpp>
#include <polder/terrain/geo_spacing.hpp>
#include <polder/terrain/samples.hpp>

namespace polder::terrain::io {

// The sample type to ask OpenImageIO for: integers as stored (asking for float would
// normalise them to 0..1), half as float.
struct StoredType {
  SampleFormat format;
  OIIO::TypeDesc request;
  const char* name;
};
std::optional<StoredType> storedType(OIIO::TypeDesc type);

// Opens an image for reading its heights (alpha kept unassociated: Terrain-RGB must not be
// premultiplied). InvalidData when OpenImageIO cannot read it.
Result<std::unique_ptr<OIIO::ImageInput>> openHeightImage(const std::filesystem::path& path);

// Why a pixel read of `input` failed, as one line, or empty when it did not. A read that
// reports success may still have met a decoder error (a corrupt strip): OpenImageIO then only
// records it, and the pixels hold whatever was decoded, so that counts as a failure too.
std::string readProblem(OIIO::ImageInput& input, bool succeeded);

// Which samples of an image hold the heights: the type to read them as, and either the R, G,
// B(, A) channels of an 8-bit image holding Terrain-RGB or Terrarium (rgb: `encoding` Auto
// until detected from the pixels) or the first channel alone.
struct ImageSampling {
  StoredType stored;
  bool rgb = false;
  HeightEncoding encoding = HeightEncoding::Auto;
  int channels = 1;  // read per pixel: 1, or 3 or 4 for rgb
};
// Fails on deep images, no samples, sample types or encodings that do not fit.
Result<ImageSampling> imageSampling(const OIIO::ImageSpec& spec, const std::string& format, const DemOptions& options);

// What the file says beyond its pixels: ground spacing, how stored values become metres.
struct FileHints {
  std::optional<GroundSpacing> spacing;
  SampleDecoding decoding;
  bool geoTiff = false;
};
Result<FileHints> readFileHints(const std::filesystem::path& path, std::uint64_t fileLength, const std::string& format,
                                const OIIO::ImageSpec& spec, const DemOptions& options);

// Errors name the problem; readDem adds the file.
Result<Dem> readImageDem(const std::filesystem::path& path, std::uint64_t fileLength, const DemOptions& options);

}  // namespace polder::terrain::io
