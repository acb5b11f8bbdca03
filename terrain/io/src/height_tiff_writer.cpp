// The float TIFF writer, with libtiff directly: OpenImageIO 2.4 cannot write GeoTIFF tags.
#include <polder/terrain/image_writer.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <tiffio.h>

#include "io_text.hpp"
#include "tiff_tags.hpp"

namespace polder::terrain {
namespace {

constexpr std::uint32_t kRowsPerStrip = 16;

struct TiffCloser {
  void operator()(TIFF* file) const { TIFFClose(file); }
};

}  // namespace

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

  std::string errors;
  std::unique_ptr<TIFF, TiffCloser> file(io::openTiff(path, "w", errors));
  if (!file) return fail(ErrorKind::Io, "cannot create the file: " + io::oneLine(errors));
  TIFF* tif = file.get();
  if (!io::setHeightTiffTags(tif, field.width, field.height, field.spacingX, field.spacingY))
    return fail(ErrorKind::Environment, "libtiff refused the GeoTIFF tags");
  TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, kRowsPerStrip);

  std::vector<float> row(std::size_t(field.width));
  for (int r = 0; r < field.height; ++r) {
    const float* south = &field.heights[field.index(0, field.height - 1 - r)];
    std::copy(south, south + field.width, row.begin());
    if (TIFFWriteScanline(tif, row.data(), std::uint32_t(r), 0) < 0)
      return fail(ErrorKind::Io, "cannot write row " + std::to_string(r) + ": " + io::oneLine(errors));
  }
  if (!TIFFFlush(tif)) return fail(ErrorKind::Io, "cannot finish the file: " + io::oneLine(errors));
  return {};
}

}  // namespace polder::terrain
