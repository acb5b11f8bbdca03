// Independent reference for tests: the usual series for the lengths of one degree on the
// WGS84 ellipsoid, to check the readers' degree-to-metre conversion.
#pragma once

#include <cmath>

namespace polder::test {

inline double metresPerDegreeLatitude(double phi) {
  const double r = phi * M_PI / 180.0;
  return 111132.954 - 559.822 * std::cos(2 * r) + 1.175 * std::cos(4 * r);
}

inline double metresPerDegreeLongitude(double phi) {
  const double r = phi * M_PI / 180.0;
  return 111412.84 * std::cos(r) - 93.5 * std::cos(3 * r) + 0.118 * std::cos(5 * r);
}

}  // namespace polder::test
