#include "image_dem.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include <polder/terrain/dem_parsing.hpp>
#include <polder/terrain/dem_validation.hpp>
#include <polder/terrain/rgb_encoding.hpp>
#include <polder/terrain/samples.hpp>

#include "io_text.hpp"
#include "tiff_tags.hpp"

namespace polder::terrain::io {
namespace {

// What a Polder-written PNG says about itself (image_writer.hpp).
struct PngMetadata {
  std::optional<GroundSpacing> spacing;
  std::optional<double> metresPerUnit;
  double offsetM = 0.0;
};

Result<PngMetadata> readPngMetadata(const OIIO::ImageSpec& spec) {
  PngMetadata metadata;
  const auto number = [&](const char* key, bool positive) -> Result<std::optional<double>> {
    const OIIO::ParamValue* found = spec.find_attribute(key, OIIO::TypeDesc::STRING);
    if (!found) return std::optional<double>();
    const std::string text = found->get_string();
    const auto value = parseNumber(text);
    if (!value || (positive && !(*value > 0.0)))
      return makeError(ErrorKind::InvalidData, std::string("PNG text ") + key + " = '" + text + "' is not a " +
                                                   (positive ? "positive " : "") + "number");
    return std::optional<double>(value);
  };
  auto spacingX = number(kPngSpacingXKey, true);
  auto spacingY = number(kPngSpacingYKey, true);
  auto metresPerUnit = number(kPngMetresPerUnitKey, false);
  auto offset = number(kPngOffsetKey, false);
  for (const auto* result : {&spacingX, &spacingY, &metresPerUnit, &offset})
    if (!*result) return result->error();
  if (*spacingX && *spacingY) metadata.spacing = GroundSpacing{**spacingX, **spacingY};
  if (*metresPerUnit && **metresPerUnit != 0.0) metadata.metresPerUnit = **metresPerUnit;
  metadata.offsetM = offset->value_or(0.0);
  return metadata;
}

}  // namespace

std::optional<StoredType> storedType(OIIO::TypeDesc type) {
  switch (OIIO::TypeDesc::BASETYPE(type.basetype)) {
    case OIIO::TypeDesc::UINT8:
      return StoredType{SampleFormat::U8, OIIO::TypeDesc::UINT8, "uint8"};
    case OIIO::TypeDesc::UINT16:
      return StoredType{SampleFormat::U16, OIIO::TypeDesc::UINT16, "uint16"};
    case OIIO::TypeDesc::INT16:
      return StoredType{SampleFormat::I16, OIIO::TypeDesc::INT16, "int16"};
    case OIIO::TypeDesc::UINT32:
      return StoredType{SampleFormat::U32, OIIO::TypeDesc::UINT32, "uint32"};
    case OIIO::TypeDesc::INT32:
      return StoredType{SampleFormat::I32, OIIO::TypeDesc::INT32, "int32"};
    case OIIO::TypeDesc::HALF:
      return StoredType{SampleFormat::F32, OIIO::TypeDesc::FLOAT, "float16"};
    case OIIO::TypeDesc::FLOAT:
      return StoredType{SampleFormat::F32, OIIO::TypeDesc::FLOAT, "float32"};
    case OIIO::TypeDesc::DOUBLE:
      return StoredType{SampleFormat::F64, OIIO::TypeDesc::DOUBLE, "float64"};
    default:
      return std::nullopt;
  }
}

Result<FileHints> readFileHints(const std::filesystem::path& path, std::uint64_t fileLength, const std::string& format,
                                const OIIO::ImageSpec& spec, const DemOptions& options) {
  FileHints hints;
  hints.decoding.scale = options.zScale;
  hints.decoding.int16Voids = options.nodataEnabled;
  if (format == "tiff") {
    const auto tags = readTiffTags(path, fileLength);
    if (!tags) return tags.error();
    hints.geoTiff = tags->georeferenced() || !tags->geoKeys.empty();
    if (!options.spacingM) {  // a spacing given by the caller overrides the file's, good or bad
      const auto spacing = geoTiffSpacing(*tags, spec.width, spec.height);
      if (!spacing) return spacing.error();
      hints.spacing = *spacing;
    }
    if (tags->gdalNodata && options.nodataEnabled) {
      const auto nodata = parseGdalNodata(*tags->gdalNodata);
      if (!nodata) return nodata.error();
      hints.decoding.nodata = *nodata;
    }
  } else if (format == "png") {
    const auto metadata = readPngMetadata(spec);
    if (!metadata) return metadata.error();
    hints.spacing = metadata->spacing;
    // The file's own scale, unless the caller gave one.
    if (metadata->metresPerUnit && options.zScale == 1.0) {
      hints.decoding.scale = *metadata->metresPerUnit;
      hints.decoding.offset = metadata->offsetM;
    }
  }
  return hints;
}

std::string readProblem(OIIO::ImageInput& input, bool succeeded) {
  const std::string recorded = input.geterror();
  if (succeeded && recorded.empty()) return {};
  return oneLine(recorded.empty() ? "the decoder failed" : recorded);
}

Result<std::unique_ptr<OIIO::ImageInput>> openHeightImage(const std::filesystem::path& path) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);  // Terrain-RGB must not be premultiplied
  std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::open(path.string(), &config);
  if (!input) return makeError(ErrorKind::InvalidData, "cannot read the image: " + oneLine(OIIO::geterror()));
  return input;
}

Result<ImageSampling> imageSampling(const OIIO::ImageSpec& spec, const std::string& format, const DemOptions& options) {
  if (spec.deep) return makeError(ErrorKind::Unsupported, "deep " + format + " images are not height maps");
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    return makeError(ErrorKind::InvalidData, "the image has no samples (" + std::to_string(spec.width) + " x " +
                                                 std::to_string(spec.height) + ", " + std::to_string(spec.nchannels) +
                                                 " channels)");
  const auto stored = storedType(spec.format);
  if (!stored)
    return makeError(ErrorKind::Unsupported,
                     std::string("samples of type ") + spec.format.c_str() + " are not supported");

  const bool rgb8 = stored->format == SampleFormat::U8 && spec.nchannels >= 3;
  const HeightEncoding encoding = options.encoding;
  if ((encoding == HeightEncoding::TerrainRgb || encoding == HeightEncoding::Terrarium) && !rgb8)
    return makeError(ErrorKind::InvalidArgument, std::string("encoding ") + heightEncodingName(encoding) +
                                                     " needs an 8-bit RGB(A) image, this one has " +
                                                     std::to_string(spec.nchannels) + " channel(s) of " + stored->name);
  ImageSampling sampling{*stored};
  sampling.rgb = rgb8 && encoding != HeightEncoding::Greyscale;
  sampling.encoding = sampling.rgb ? encoding : HeightEncoding::Greyscale;
  sampling.channels = sampling.rgb ? (spec.alpha_channel == 3 ? 4 : 3) : 1;
  return sampling;
}

Result<Dem> readImageDem(const std::filesystem::path& path, std::uint64_t fileLength, const DemOptions& options) {
  auto opened = openHeightImage(path);
  if (!opened) return opened.error();
  std::unique_ptr<OIIO::ImageInput> input = std::move(*opened);
  const OIIO::ImageSpec spec = input->spec();
  const std::string format = input->format_name();
  auto sampling = imageSampling(spec, format, options);
  if (!sampling) return sampling.error();
  const StoredType* stored = &sampling->stored;
  const bool readRgb = sampling->rgb;
  HeightEncoding encoding = sampling->encoding;
  const int channels = sampling->channels;

  // Everything that could make the read pointless or too large is checked before the pixels.
  if (Status size = checkRasterSize(std::uint64_t(spec.width), std::uint64_t(spec.height),
                                    demBytesPerSample(std::uint64_t(channels) * stored->request.size()),
                                    options.memoryLimitBytes);
      !size)
    return size.error();
  auto hints = readFileHints(path, fileLength, format, spec, options);
  if (!hints) return hints.error();

  const std::size_t samples = std::size_t(spec.width) * std::size_t(spec.height);
  std::vector<std::byte> pixels(samples * std::size_t(channels) * stored->request.size());
  const bool read = input->read_image(0, 0, 0, channels, stored->request, pixels.data());
  if (const std::string problem = readProblem(*input, read); !problem.empty())
    return makeError(ErrorKind::InvalidData, "cannot read the pixels: " + problem);
  input->close();

  DemInfo info;
  info.format = hints->geoTiff ? "geotiff" : format;
  Heightfield field;
  if (readRgb) {
    const RgbView view{reinterpret_cast<const std::uint8_t*>(pixels.data()), spec.width, spec.height, channels};
    if (encoding == HeightEncoding::Auto) {
      const auto detected = detectRgbEncoding(view);
      if (!detected) return detected.error();
      encoding = *detected;
    }
    if (encoding != HeightEncoding::Greyscale) {
      field = decodeRgbHeights(view, encoding, options.nodataEnabled);
      info.encoding = heightEncodingName(encoding);
    }
  }
  if (info.encoding.empty()) {
    SampleSource source;
    source.data = pixels.data();
    source.format = stored->format;
    source.width = spec.width;
    source.height = spec.height;
    source.channels = channels;
    auto decoded = decodeSamples(source, hints->decoding);
    if (!decoded) return decoded.error();
    field = std::move(*decoded);
    info.encoding = stored->name;
  }
  std::vector<std::byte>().swap(pixels);  // give the memory back before void filling needs its own
  return finishDem(std::move(field), std::move(info), options, hints->spacing);
}

}  // namespace polder::terrain::io
