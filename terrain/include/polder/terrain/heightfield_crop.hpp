// A rectangle cut out of a heightfield (benchmark presets such as Chuang 2001's 660 x 660
// samples from the middle of a larger DEM).
#pragma once

#include <polder/result.hpp>
#include <polder/terrain/heightfield.hpp>

namespace polder::terrain {

// Samples [x0, x0 + width) x [y0, y0 + height) (row 0 south, as in Heightfield), same spacing.
// InvalidArgument when the rectangle is empty or leaves the field.
Result<Heightfield> cropHeightfield(const Heightfield& field, int x0, int y0, int width, int height);

// The width x height samples around the field's centre.
Result<Heightfield> cropCentre(const Heightfield& field, int width, int height);

}  // namespace polder::terrain
