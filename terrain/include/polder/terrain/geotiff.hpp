// GeoTIFF georeferencing as plain data: the adapter reads the tags (with libtiff), this turns
// them into a ground spacing in metres and a no-data value.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <polder/result.hpp>
#include <polder/terrain/geo_spacing.hpp>

namespace polder::terrain {

inline constexpr std::uint16_t kTagModelPixelScale = 33550;
inline constexpr std::uint16_t kTagModelTiepoint = 33922;
inline constexpr std::uint16_t kTagModelTransformation = 34264;
inline constexpr std::uint16_t kTagGeoKeyDirectory = 34735;
inline constexpr std::uint16_t kTagGdalNodata = 42113;

// The georeferencing tags of a TIFF; empty when absent.
struct GeoTiffTags {
  std::vector<double> pixelScale;         // ModelPixelScale: (sx, sy, sz)
  std::vector<double> tiepoint;           // ModelTiepoint: (i, j, k, x, y, z), ...
  std::vector<double> transformation;     // ModelTransformation: 4x4, row-major
  std::vector<std::uint16_t> geoKeys;     // GeoKeyDirectory: header, then 4 shorts per key
  std::optional<std::string> gdalNodata;  // GDAL_NODATA, ASCII

  bool georeferenced() const { return !pixelScale.empty() || !transformation.empty(); }
};

// The value of a GeoKey stored in the directory itself, if present.
std::optional<std::uint16_t> geoKeyValue(const std::vector<std::uint16_t>& geoKeys, std::uint16_t key);

// The ground spacing of a width x height raster in metres, or nullopt when the tags give no
// pixel size. Geographic rasters (degrees) and Web Mercator (EPSG:3857) are converted at
// the raster's centre latitude; projected ones use their linear unit (metre, foot); a pixel
// size without GeoKeys is taken as metres. Fails (Unsupported) on units it does not know,
// (InvalidData) on a pixel size that is given but zero, negative or not finite.
Result<std::optional<GroundSpacing>> geoTiffSpacing(const GeoTiffTags& tags, int width, int height);

// The GDAL_NODATA text ("-32768", "nan", "-3.4028234663852886e+38") as a number.
Result<double> parseGdalNodata(std::string_view text);

}  // namespace polder::terrain
