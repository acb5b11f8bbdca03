// GeoTIFF 1.0 (OGC 19-008r4): GeoKeyDirectory layout, model types and unit codes.
#include <polder/terrain/geotiff.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace polder::terrain {
namespace {

constexpr std::uint16_t kGTModelTypeGeoKey = 1024;
constexpr std::uint16_t kGTRasterTypeGeoKey = 1025;
constexpr std::uint16_t kGeographicTypeGeoKey = 2048;
constexpr std::uint16_t kGeogAngularUnitsGeoKey = 2054;
constexpr std::uint16_t kProjectedCSTypeGeoKey = 3072;
constexpr std::uint16_t kProjLinearUnitsGeoKey = 3076;

constexpr std::uint16_t kModelTypeProjected = 1;
constexpr std::uint16_t kModelTypeGeographic = 2;
constexpr std::uint16_t kRasterPixelIsPoint = 2;

Result<double> angularUnitDegrees(std::optional<std::uint16_t> code) {
  switch (code.value_or(9102)) {
    case 9101:
      return 180.0 / std::numbers::pi;  // radian
    case 9102:
      return 1.0;  // degree
    case 9103:
      return 1.0 / 60.0;  // arc-minute
    case 9104:
      return 1.0 / 3600.0;  // arc-second
    case 9105:
      return 0.9;  // grad
  }
  return makeError(ErrorKind::Unsupported, "GeoTIFF angular unit " + std::to_string(*code) + " is not supported");
}

Result<double> linearUnitMetres(std::optional<std::uint16_t> code) {
  switch (code.value_or(9001)) {
    case 9001:
      return 1.0;  // metre
    case 9002:
      return 0.3048;  // international foot
    case 9003:
      return 1200.0 / 3937.0;  // US survey foot
    case 9036:
      return 1000.0;  // kilometre
  }
  return makeError(ErrorKind::Unsupported, "GeoTIFF linear unit " + std::to_string(*code) + " is not supported");
}

std::string formatNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

}  // namespace

std::optional<std::uint16_t> geoKeyValue(const std::vector<std::uint16_t>& geoKeys, std::uint16_t key) {
  if (geoKeys.size() < 4) return std::nullopt;
  const std::size_t count = std::min<std::size_t>(geoKeys[3], (geoKeys.size() - 4) / 4);
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint16_t* entry = &geoKeys[4 + 4 * k];  // id, tag location, count, value
    if (entry[0] == key && entry[1] == 0 && entry[2] == 1) return entry[3];
  }
  return std::nullopt;
}

Result<std::optional<GroundSpacing>> geoTiffSpacing(const GeoTiffTags& tags, int width, int height) {
  const bool pixelIsPoint = geoKeyValue(tags.geoKeys, kGTRasterTypeGeoKey) == kRasterPixelIsPoint;
  // Raster coordinates of the raster's centre: pixel corners sit on integers for PixelIsArea,
  // pixel centres for PixelIsPoint.
  const double centreI = pixelIsPoint ? (width - 1) * 0.5 : width * 0.5;
  const double centreJ = pixelIsPoint ? (height - 1) * 0.5 : height * 0.5;

  double sx = 0.0, sy = 0.0;
  // Model y (northing or latitude) of the centre; without a tiepoint it is unknown and the
  // equator is taken.
  double centreY = 0.0;
  const bool scaled = tags.pixelScale.size() >= 2 || tags.transformation.size() >= 16;
  if (tags.pixelScale.size() >= 2) {
    sx = std::abs(tags.pixelScale[0]);
    sy = std::abs(tags.pixelScale[1]);
    if (tags.tiepoint.size() >= 6) centreY = tags.tiepoint[4] - (centreJ - tags.tiepoint[1]) * sy;
  } else if (tags.transformation.size() >= 16) {
    const std::vector<double>& m = tags.transformation;
    sx = std::hypot(m[0], m[4]);
    sy = std::hypot(m[1], m[5]);
    centreY = m[4] * centreI + m[5] * centreJ + m[7];
  }
  if (!scaled) return std::optional<GroundSpacing>();
  if (!(sx > 0.0 && sy > 0.0 && std::isfinite(sx) && std::isfinite(sy)))
    return makeError(ErrorKind::InvalidData, "the GeoTIFF pixel size " + formatNumber(sx) + " x " + formatNumber(sy) +
                                                 " is not positive and finite (give --spacing to override it)");
  if (!std::isfinite(centreY)) centreY = 0.0;

  std::optional<std::uint16_t> modelType = geoKeyValue(tags.geoKeys, kGTModelTypeGeoKey);
  if (!modelType && geoKeyValue(tags.geoKeys, kProjectedCSTypeGeoKey)) modelType = kModelTypeProjected;
  if (!modelType && geoKeyValue(tags.geoKeys, kGeographicTypeGeoKey)) modelType = kModelTypeGeographic;

  if (modelType == kModelTypeGeographic) {
    const auto degrees = angularUnitDegrees(geoKeyValue(tags.geoKeys, kGeogAngularUnitsGeoKey));
    if (!degrees) return degrees.error();
    // Keep clear of the poles, where an east-west spacing would vanish.
    const double latitude = std::clamp(centreY * *degrees, -89.0, 89.0);
    const GroundSpacing perDegree = metresPerDegree(latitude);
    return std::optional<GroundSpacing>(GroundSpacing{sx * *degrees * perDegree.x, sy * *degrees * perDegree.y});
  }
  if (modelType && modelType != kModelTypeProjected)
    return makeError(ErrorKind::Unsupported, "GeoTIFF model type " + std::to_string(*modelType) +
                                                 " (neither projected nor geographic) is not supported");
  const auto metres = linearUnitMetres(geoKeyValue(tags.geoKeys, kProjLinearUnitsGeoKey));
  if (!metres) return metres.error();
  const auto crs = geoKeyValue(tags.geoKeys, kProjectedCSTypeGeoKey);
  if (crs == 3857 || crs == 3785) {
    // Web Mercator stretches the ground by 1 / cos(latitude) in both directions.
    const double latitude = std::clamp(webMercatorLatitude(centreY * *metres), -89.0, 89.0);
    const double shrink = std::cos(latitude * std::numbers::pi / 180.0);
    return std::optional<GroundSpacing>(GroundSpacing{sx * *metres * shrink, sy * *metres * shrink});
  }
  return std::optional<GroundSpacing>(GroundSpacing{sx * *metres, sy * *metres});
}

Result<double> parseGdalNodata(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '+')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\0')) text.remove_suffix(1);
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size())
    return makeError(ErrorKind::InvalidData, "GDAL_NODATA tag '" + std::string(text) + "' is not a number");
  return value;
}

}  // namespace polder::terrain
