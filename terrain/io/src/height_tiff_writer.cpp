// The float TIFF writer of a whole heightfield: the streamed writer, a band at a time.
#include <polder/terrain/image_writer.hpp>

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include <polder/terrain/height_tiff_stream.hpp>

namespace polder::terrain {

Status writeHeightTiffFloat(const std::filesystem::path& path, const Heightfield& field) {
  const auto fail = [&](ErrorKind kind, const std::string& message) {
    return makeError(kind, path.string() + ": " + message);
  };
  if (field.width <= 0 || field.height <= 0 || field.heights.size() != field.sampleCount())
    return fail(ErrorKind::InvalidArgument, "the heightfield is empty or inconsistent");
  if (!(field.spacingX > 0.0 && field.spacingY > 0.0 && std::isfinite(field.spacingX) && std::isfinite(field.spacingY)))
    return fail(ErrorKind::InvalidArgument, "the spacing is not positive and finite");
  if (std::any_of(field.heights.begin(), field.heights.end(), [](float h) { return !std::isfinite(h); }))
    return fail(ErrorKind::InvalidArgument, "a height is not finite");

  // The streamed writer does the writing: tiled, atomic, every libtiff failure reported.
  auto stream = HeightTiffStream::create(path, field.width, field.height, field.spacingX, field.spacingY);
  if (!stream) return stream.error();
  const int band = HeightTiffStream::kTileSize;
  std::vector<float> rows(std::size_t(band) * std::size_t(field.width));
  for (int first = 0; first < field.height; first += band) {
    const int count = std::min(band, field.height - first);
    for (int r = 0; r < count; ++r) {
      const float* row = &field.heights[field.index(0, field.height - 1 - (first + r))];
      std::copy(row, row + field.width, rows.begin() + std::ptrdiff_t(r) * field.width);
    }
    if (Status written = (*stream)->writeRows(
            count, std::span<const float>(rows.data(), std::size_t(count) * std::size_t(field.width)));
        !written)
      return written;
  }
  return (*stream)->finish();
}

}  // namespace polder::terrain
