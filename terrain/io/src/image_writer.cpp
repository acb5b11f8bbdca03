// The PNG writers (OpenImageIO). The float TIFF writer is in height_tiff_writer.cpp.
#include <polder/terrain/image_writer.hpp>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <polder/file_contents.hpp>

#include "io_text.hpp"

namespace polder::terrain {
namespace {

Error named(const std::filesystem::path& path, ErrorKind kind, const std::string& message) {
  return makeError(kind, path.string() + ": " + message);
}

// Encodes one image in memory through OpenImageIO, then writes it whole or not at all
// (core::writeFileContents): the encoder's own file output does not report a full disk.
// Errors name the file.
Status writeImage(const std::filesystem::path& path, const OIIO::ImageSpec& spec, const void* pixels) {
  std::unique_ptr<OIIO::ImageOutput> output = OIIO::ImageOutput::create("png");
  if (!output) return named(path, ErrorKind::Environment, "no PNG writer: " + io::oneLine(OIIO::geterror()));
  if (!output->supports("ioproxy"))
    return named(path, ErrorKind::Environment, "the PNG writer cannot encode to memory");
  std::vector<unsigned char> encoded;
  OIIO::Filesystem::IOVecOutput memory(encoded);
  if (!output->set_ioproxy(&memory) || !output->open(path.string(), spec))
    return named(path, ErrorKind::Io, "cannot encode the image: " + io::oneLine(output->geterror()));
  const bool written = output->write_image(spec.format, pixels);
  const bool closed = output->close();
  if (!written || !closed)
    return named(path, ErrorKind::Io, "cannot encode the image: " + io::oneLine(output->geterror()));
  return core::writeFileContents(path, std::string_view(reinterpret_cast<const char*>(encoded.data()), encoded.size()));
}

Status checkField(const std::filesystem::path& path, const Heightfield& field) {
  if (field.width <= 0 || field.height <= 0 || field.heights.size() != field.sampleCount())
    return named(path, ErrorKind::InvalidArgument,
                 "the heightfield is empty or inconsistent (" + std::to_string(field.width) + " x " +
                     std::to_string(field.height) + ", " + std::to_string(field.heights.size()) + " heights)");
  if (!(field.spacingX > 0.0 && field.spacingY > 0.0 && std::isfinite(field.spacingX) && std::isfinite(field.spacingY)))
    return named(path, ErrorKind::InvalidArgument, "the spacing is not positive and finite");
  const auto bad = std::find_if(field.heights.begin(), field.heights.end(), [](float h) { return !std::isfinite(h); });
  if (bad != field.heights.end()) {
    const std::size_t i = std::size_t(bad - field.heights.begin());
    return named(path, ErrorKind::InvalidArgument,
                 "height at (" + std::to_string(i % std::size_t(field.width)) + ", " +
                     std::to_string(i / std::size_t(field.width)) + ") is not finite");
  }
  return {};
}

}  // namespace

HeightQuantization fitHeightQuantization(const Heightfield& field) {
  if (field.heights.empty()) return {};
  const auto [low, high] = std::minmax_element(field.heights.begin(), field.heights.end());
  const double range = double(*high) - double(*low);
  return {range > 0.0 && std::isfinite(range) ? range / 65535.0 : 1.0, double(*low)};
}

Status writeHeightPng16(const std::filesystem::path& path, const Heightfield& field,
                        std::optional<HeightQuantization> quantization) {
  if (Status valid = checkField(path, field); !valid) return valid;
  const HeightQuantization q = quantization.value_or(fitHeightQuantization(field));
  if (!(q.metresPerUnit > 0.0 && std::isfinite(q.metresPerUnit) && std::isfinite(q.offsetM)))
    return named(path, ErrorKind::InvalidArgument, "the quantization's metres per unit must be positive and finite");

  std::vector<std::uint16_t> values(field.sampleCount());
  for (int row = 0; row < field.height; ++row) {
    const int y = field.height - 1 - row;  // files store the north row first
    for (int x = 0; x < field.width; ++x) {
      const double value = (double(field.at(x, y)) - q.offsetM) / q.metresPerUnit;
      if (!(value >= -0.5 && value <= 65535.5))
        return named(path, ErrorKind::InvalidArgument,
                     "height " + std::to_string(field.at(x, y)) + " m does not fit 16 bits at " +
                         io::formatExact(q.metresPerUnit) + " m per unit from " + io::formatExact(q.offsetM) + " m");
      values[std::size_t(row) * std::size_t(field.width) + std::size_t(x)] =
          std::uint16_t(std::clamp(std::lround(value), 0L, 65535L));
    }
  }
  OIIO::ImageSpec spec(field.width, field.height, 1, OIIO::TypeDesc::UINT16);
  spec.attribute(io::kPngSpacingXKey, io::formatExact(field.spacingX));
  spec.attribute(io::kPngSpacingYKey, io::formatExact(field.spacingY));
  spec.attribute(io::kPngMetresPerUnitKey, io::formatExact(q.metresPerUnit));
  spec.attribute(io::kPngOffsetKey, io::formatExact(q.offsetM));
  return writeImage(path, spec, values.data());
}

Status writeRgbaPng(const std::filesystem::path& path, const RgbaImage& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != std::size_t(image.width) * std::size_t(image.height) * 4)
    return named(path, ErrorKind::InvalidArgument,
                 "the image is empty or inconsistent (" + std::to_string(image.width) + " x " +
                     std::to_string(image.height) + ", " + std::to_string(image.pixels.size()) + " bytes)");
  OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::UINT8);
  spec.alpha_channel = 3;
  spec.attribute("oiio:UnassociatedAlpha", 1);  // the pixels are not premultiplied
  return writeImage(path, spec, image.pixels.data());
}

}  // namespace polder::terrain
