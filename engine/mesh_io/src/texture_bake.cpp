#include "texture_bake.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <new>
#include <string>
#include <system_error>

#include <polder/one_line.hpp>
#include <polder/png_check.hpp>

namespace polder::mesh_io::detail {
namespace {

// Beyond this many samples (4 GiB of floats) the image is refused rather than allocated.
constexpr std::uint64_t kMaxSamples = std::uint64_t(1) << 30;

Error imageError(const std::filesystem::path& image, ErrorKind kind, const std::string& message) {
  return makeError(kind, "texture " + image.string() + ": " + message);
}

// Texture coordinate to a position in texel units, repeating outside [0, 1].
double texelPosition(double coordinate, int size) {
  if (coordinate < 0.0 || coordinate > 1.0) coordinate -= std::floor(coordinate);
  return std::clamp(coordinate * size - 0.5, 0.0, double(size - 1));
}

}  // namespace

Result<std::vector<glm::vec4>> sampleTexture(const std::filesystem::path& image, const std::vector<glm::vec2>& uvs) {
  std::error_code code;
  const auto status = std::filesystem::status(image, code);
  if (!std::filesystem::is_regular_file(status))
    return imageError(image, ErrorKind::Io,
                      std::filesystem::exists(status) ? "not a regular file" : "the file does not exist");
  // libpng prints its complaint about corrupt data to stderr: such files are found first.
  if (Status structure = image_check::checkIfPng(image); !structure)
    return imageError(image, structure.error().kind, structure.error().message);
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);  // colours as painted, not premultiplied by alpha
  std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::open(image.string(), &config);
  if (!input) return imageError(image, ErrorKind::InvalidData, "cannot read the image: " + oneLine(OIIO::geterror()));
  const OIIO::ImageSpec spec = input->spec();
  const int width = spec.width, height = spec.height, channels = spec.nchannels;
  if (width <= 0 || height <= 0 || channels <= 0 || spec.depth > 1)
    return imageError(image, ErrorKind::InvalidData, "the image is empty or not two-dimensional");
  const std::uint64_t sampleCount = std::uint64_t(width) * std::uint64_t(height) * std::uint64_t(channels);
  if (sampleCount > kMaxSamples) return imageError(image, ErrorKind::OutOfMemory, "the image is too large to bake");
  std::vector<float> pixels;
  try {
    pixels.resize(sampleCount);
  } catch (const std::bad_alloc&) {
    return imageError(image, ErrorKind::OutOfMemory, "not enough memory for the image");
  }
  // Success with a recorded error is a corrupt image decoded to garbage: refused too.
  const bool read = input->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data());
  const std::string problem = input->geterror();
  if (!read || !problem.empty())
    return imageError(image, ErrorKind::InvalidData,
                      "cannot decode the image: " + oneLine(problem.empty() ? "the decoder failed" : problem));
  input->close();

  const auto texel = [&](int x, int y) {
    const float* p = &pixels[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * std::size_t(channels)];
    if (channels < 3) return glm::vec4(p[0], p[0], p[0], channels == 2 ? p[1] : 1.0f);
    return glm::vec4(p[0], p[1], p[2], channels >= 4 ? p[3] : 1.0f);
  };
  std::vector<glm::vec4> colours(uvs.size());
  for (std::size_t i = 0; i < uvs.size(); ++i) {
    const glm::vec2 uv = uvs[i];
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
      return makeError(ErrorKind::InvalidData, "vertex " + std::to_string(i) + " has a non-finite texture coordinate");
    const double x = texelPosition(uv.x, width);
    const double y = texelPosition(1.0 - double(uv.y), height);  // image row 0 is the top
    const int x0 = int(x), y0 = int(y);
    const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
    const float fx = float(x - x0), fy = float(y - y0);
    const glm::vec4 top = glm::mix(texel(x0, y0), texel(x1, y0), fx);
    const glm::vec4 bottom = glm::mix(texel(x0, y1), texel(x1, y1), fx);
    const glm::vec4 colour = glm::mix(top, bottom, fy);
    colours[i] = glm::vec4(unitColour(colour.r), unitColour(colour.g), unitColour(colour.b), unitColour(colour.a));
  }
  return colours;
}

}  // namespace polder::mesh_io::detail
