// Ground distances on the Earth, for turning georeferenced sample spacings (degrees, Web
// Mercator units) into metres.
#pragma once

namespace polder::terrain {

// Metres between two samples along x (east) and y (north).
struct GroundSpacing {
  double x = 1.0;
  double y = 1.0;
};

// Metres per degree of longitude (x) and of latitude (y) at a latitude, on the WGS84
// ellipsoid (x is the parallel's length, so it shrinks with cos(latitude)).
GroundSpacing metresPerDegree(double latitudeDeg);

// Latitude in degrees of a Web Mercator (EPSG:3857) northing in metres.
double webMercatorLatitude(double northingM);

}  // namespace polder::terrain
