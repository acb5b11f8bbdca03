#include <polder/terrain/geo_spacing.hpp>

#include <cmath>
#include <numbers>

namespace polder::terrain {
namespace {

constexpr double kWgs84SemiMajorM = 6378137.0;
constexpr double kWgs84Flattening = 1.0 / 298.257223563;
constexpr double kDegree = std::numbers::pi / 180.0;

}  // namespace

GroundSpacing metresPerDegree(double latitudeDeg) {
  // Radii of curvature of the ellipsoid: along the meridian (M) and the prime vertical (N).
  constexpr double e2 = kWgs84Flattening * (2.0 - kWgs84Flattening);
  const double s = std::sin(latitudeDeg * kDegree);
  const double w = 1.0 - e2 * s * s;
  const double meridian = kWgs84SemiMajorM * (1.0 - e2) / (w * std::sqrt(w));
  const double primeVertical = kWgs84SemiMajorM / std::sqrt(w);
  return {primeVertical * std::cos(latitudeDeg * kDegree) * kDegree, meridian * kDegree};
}

double webMercatorLatitude(double northingM) {
  // EPSG:3857 projects the WGS84 coordinates as if on a sphere of the semi-major axis.
  return (2.0 * std::atan(std::exp(northingM / kWgs84SemiMajorM)) - std::numbers::pi / 2.0) / kDegree;
}

}  // namespace polder::terrain
