#include <polder/terrain/heightfield_crop.hpp>

#include <algorithm>
#include <string>

namespace polder::terrain {

Result<Heightfield> cropHeightfield(const Heightfield& field, int x0, int y0, int width, int height) {
  if (width < 2 || height < 2 || x0 < 0 || y0 < 0 || x0 + width > field.width || y0 + height > field.height)
    return makeError(ErrorKind::InvalidArgument,
                     "cannot cut " + std::to_string(width) + " x " + std::to_string(height) + " samples at (" +
                         std::to_string(x0) + ", " + std::to_string(y0) + ") from a " + std::to_string(field.width) +
                         " x " + std::to_string(field.height) + " DEM");
  Heightfield crop(width, height, field.spacingX, field.spacingY);
  for (int y = 0; y < height; ++y) {
    const auto row = field.heights.begin() + std::ptrdiff_t(field.index(x0, y0 + y));
    std::copy(row, row + width, crop.heights.begin() + std::ptrdiff_t(crop.index(0, y)));
  }
  return crop;
}

Result<Heightfield> cropCentre(const Heightfield& field, int width, int height) {
  return cropHeightfield(field, (field.width - width) / 2, (field.height - height) / 2, width, height);
}

}  // namespace polder::terrain
