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
  if (!io::declareGeoTiffTags(file.get())) return fail(ErrorKind::Environment, "libtiff refused the GeoTIFF tags");

  TIFF* tif = file.get();
  TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, std::uint32_t(field.width));
  TIFFSetField(tif, TIFFTAG_IMAGELENGTH, std::uint32_t(field.height));
  TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
  TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 32);
  TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_IEEEFP);
  TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
  TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(tif, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
  TIFFSetField(tif, TIFFTAG_PREDICTOR, PREDICTOR_FLOATINGPOINT);
  TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, kRowsPerStrip);

  // A local projected CRS in metres; the raster's first (north-west) sample, as a point,
  // sits at the world frame's (0, extentY): the south-west sample is the origin.
  const double pixelScale[3] = {field.spacingX, field.spacingY, 0.0};
  const double tiepoint[6] = {0.0, 0.0, 0.0, 0.0, field.extentY(), 0.0};
  const std::uint16_t geoKeys[] = {
      1,    1, 0, 4,      // directory version 1.1.0, 4 keys
      1024, 0, 1, 1,      // GTModelTypeGeoKey = projected
      1025, 0, 1, 2,      // GTRasterTypeGeoKey = PixelIsPoint
      3072, 0, 1, 32767,  // ProjectedCSTypeGeoKey = user-defined
      3076, 0, 1, 9001,   // ProjLinearUnitsGeoKey = metre
  };
  TIFFSetField(tif, kTagModelPixelScale, 3, pixelScale);
  TIFFSetField(tif, kTagModelTiepoint, 6, tiepoint);
  TIFFSetField(tif, kTagGeoKeyDirectory, int(sizeof geoKeys / sizeof geoKeys[0]), geoKeys);

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
