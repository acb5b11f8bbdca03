#include "tiff_tags.hpp"

#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include <tiffio.h>

#include "io_text.hpp"

namespace polder::terrain::io {
namespace {

int collectError(TIFF*, void* userData, const char* module, const char* format, va_list arguments) {
  char text[512];
  std::vsnprintf(text, sizeof text, format, arguments);
  std::string& errors = *static_cast<std::string*>(userData);
  if (!errors.empty()) errors += "; ";
  errors += module ? std::string(module) + ": " + text : std::string(text);
  return 1;  // handled: nothing reaches libtiff's global handler (which prints)
}

int ignoreWarning(TIFF*, void*, const char*, const char*, va_list) { return 1; }

struct TiffCloser {
  void operator()(TIFF* file) const { TIFFClose(file); }
};

// A tag stored as an array of T. Tags libtiff does not know are read as "anonymous" fields
// (count passed as uint32); tags a library has declared may pass a uint16 count instead.
template <class T>
std::vector<T> readArray(TIFF* file, std::uint32_t tag, TIFFDataType type) {
  const TIFFField* field = TIFFFindField(file, tag, TIFF_ANY);
  if (!field || TIFFFieldDataType(field) != type || !TIFFFieldPassCount(field)) return {};
  void* data = nullptr;
  std::uint32_t count = 0;
  if (TIFFFieldReadCount(field) == TIFF_VARIABLE2) {
    if (!TIFFGetField(file, tag, &count, &data)) return {};
  } else if (TIFFFieldReadCount(field) == TIFF_VARIABLE) {
    std::uint16_t shortCount = 0;
    if (!TIFFGetField(file, tag, &shortCount, &data)) return {};
    count = shortCount;
  } else {
    return {};
  }
  if (!data) return {};
  const T* values = static_cast<const T*>(data);
  return std::vector<T>(values, values + count);
}

std::optional<std::string> readAscii(TIFF* file, std::uint32_t tag) {
  const TIFFField* field = TIFFFindField(file, tag, TIFF_ANY);
  if (!field || TIFFFieldDataType(field) != TIFF_ASCII) return std::nullopt;
  if (TIFFFieldPassCount(field)) {
    const std::vector<char> text = readArray<char>(file, tag, TIFF_ASCII);
    if (text.empty()) return std::nullopt;
    return std::string(text.data(), strnlen(text.data(), text.size()));
  }
  const char* text = nullptr;
  if (!TIFFGetField(file, tag, &text) || !text) return std::nullopt;
  return std::string(text);
}

}  // namespace

tiff* openTiff(const std::filesystem::path& path, const char* mode, std::string& errors) {
  TIFFOpenOptions* options = TIFFOpenOptionsAlloc();
  if (!options) return nullptr;
  TIFFOpenOptionsSetErrorHandlerExtR(options, collectError, &errors);
  TIFFOpenOptionsSetWarningHandlerExtR(options, ignoreWarning, nullptr);
  TIFF* file = TIFFOpenExt(path.c_str(), mode, options);
  TIFFOpenOptionsFree(options);
  return file;
}

Result<GeoTiffTags> readTiffTags(const std::filesystem::path& path, std::uint64_t fileLength) {
  std::string errors;
  std::unique_ptr<TIFF, TiffCloser> file(openTiff(path, "r", errors));
  if (!file) return makeError(ErrorKind::InvalidData, "cannot read the TIFF tags: " + oneLine(errors));

  const bool tiled = TIFFIsTiled(file.get());
  const std::uint32_t pieces = tiled ? TIFFNumberOfTiles(file.get()) : TIFFNumberOfStrips(file.get());
  for (std::uint32_t i = 0; i < pieces; ++i) {
    const std::uint64_t end = TIFFGetStrileOffset(file.get(), i) + TIFFGetStrileByteCount(file.get(), i);
    if (end > fileLength)
      return makeError(ErrorKind::InvalidData, std::string("truncated TIFF: ") + (tiled ? "tile " : "strip ") +
                                                   std::to_string(i) + " ends at byte " + std::to_string(end) +
                                                   ", the file at byte " + std::to_string(fileLength));
  }
  GeoTiffTags tags;
  tags.pixelScale = readArray<double>(file.get(), kTagModelPixelScale, TIFF_DOUBLE);
  tags.tiepoint = readArray<double>(file.get(), kTagModelTiepoint, TIFF_DOUBLE);
  tags.transformation = readArray<double>(file.get(), kTagModelTransformation, TIFF_DOUBLE);
  tags.geoKeys = readArray<std::uint16_t>(file.get(), kTagGeoKeyDirectory, TIFF_SHORT);
  tags.gdalNodata = readAscii(file.get(), kTagGdalNodata);
  return tags;
}

bool declareGeoTiffTags(tiff* file) {
  static const TIFFFieldInfo kFields[] = {
      {kTagModelPixelScale, TIFF_VARIABLE, TIFF_VARIABLE, TIFF_DOUBLE, FIELD_CUSTOM, 1, 1,
       const_cast<char*>("ModelPixelScaleTag")},
      {kTagModelTiepoint, TIFF_VARIABLE, TIFF_VARIABLE, TIFF_DOUBLE, FIELD_CUSTOM, 1, 1,
       const_cast<char*>("ModelTiepointTag")},
      {kTagGeoKeyDirectory, TIFF_VARIABLE, TIFF_VARIABLE, TIFF_SHORT, FIELD_CUSTOM, 1, 1,
       const_cast<char*>("GeoKeyDirectoryTag")},
      {kTagGdalNodata, TIFF_VARIABLE, TIFF_VARIABLE, TIFF_ASCII, FIELD_CUSTOM, 1, 0, const_cast<char*>("GDAL_NODATA")},
  };
  return TIFFMergeFieldInfo(file, kFields, sizeof kFields / sizeof kFields[0]) == 0;
}

bool setHeightTiffTags(TIFF* tif, int width, int height, double spacingX, double spacingY) {
  if (!declareGeoTiffTags(tif)) return false;
  TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, std::uint32_t(width));
  TIFFSetField(tif, TIFFTAG_IMAGELENGTH, std::uint32_t(height));
  TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
  TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 32);
  TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_IEEEFP);
  TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
  TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(tif, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
  TIFFSetField(tif, TIFFTAG_PREDICTOR, PREDICTOR_FLOATINGPOINT);

  // A local projected CRS in metres; the raster's first (north-west) sample, as a point,
  // sits at the world frame's (0, extentY): the south-west sample is the origin.
  const double pixelScale[3] = {spacingX, spacingY, 0.0};
  const double tiepoint[6] = {0.0, 0.0, 0.0, 0.0, double(height - 1) * spacingY, 0.0};
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
  return true;
}

}  // namespace polder::terrain::io
