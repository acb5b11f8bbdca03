// The surface a frame's screen-space error is measured against (screen_error.hpp): the height
// under a point, and whether a ray meets it. The full resolution in Embree (QueryScene), or
// read from a pyramid's level-0 tiles (PyramidSurface) where the DEM does not fit in memory.
//
// Thread contract: both queries may be called from any number of threads at once.
#pragma once

#include <optional>

#include <polder/query/ray.hpp>

namespace polder::query {

class TrueSurface {
 public:
  virtual ~TrueSurface() = default;
  // Height of the surface at world (x, y); nullopt outside its footprint or over no-data.
  virtual std::optional<double> height(double x, double y) const = 0;
  // True when the ray meets the surface within its distances.
  virtual bool meets(const QueryRay& ray) const = 0;
};

}  // namespace polder::query
