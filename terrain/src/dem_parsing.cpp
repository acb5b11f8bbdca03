#include <polder/terrain/dem_parsing.hpp>

#include <charconv>
#include <string>

namespace polder::terrain {
namespace {

// A whole, positive int (no sign, no spaces, no overflow).
bool parsePositiveInt(std::string_view text, int& value) {
  if (text.empty()) return false;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size() && value > 0;
}

Error rawLayoutError(std::string_view text, std::string_view problem) {
  return makeError(ErrorKind::InvalidArgument, "raw layout '" + std::string(text) + "': " + std::string(problem) +
                                                   " (expected WxH:u16|i16|f32[:le|be], e.g. 1024x1024:u16)");
}

}  // namespace

Result<RawLayout> parseRawLayout(std::string_view text) {
  const std::size_t firstColon = text.find(':');
  if (firstColon == std::string_view::npos) return rawLayoutError(text, "no sample type");
  const std::string_view size = text.substr(0, firstColon);
  std::string_view rest = text.substr(firstColon + 1);
  const std::size_t secondColon = rest.find(':');
  const std::string_view type = rest.substr(0, secondColon);
  const std::string_view order =
      secondColon == std::string_view::npos ? std::string_view() : rest.substr(secondColon + 1);

  RawLayout layout;
  const std::size_t x = size.find('x');
  if (x == std::string_view::npos || !parsePositiveInt(size.substr(0, x), layout.width) ||
      !parsePositiveInt(size.substr(x + 1), layout.height))
    return rawLayoutError(text, "the size must be two positive whole numbers WxH");

  if (type == "u16")
    layout.type = SampleType::U16;
  else if (type == "i16")
    layout.type = SampleType::I16;
  else if (type == "f32")
    layout.type = SampleType::F32;
  else
    return rawLayoutError(text, "unknown sample type '" + std::string(type) + "'");

  if (secondColon == std::string_view::npos || order == "le")
    layout.bigEndian = false;
  else if (order == "be")
    layout.bigEndian = true;
  else
    return rawLayoutError(text, "unknown byte order '" + std::string(order) + "'");
  return layout;
}

std::string rawLayoutName(const RawLayout& layout) {
  const char* type = layout.type == SampleType::U16 ? "u16" : layout.type == SampleType::I16 ? "i16" : "f32";
  return std::to_string(layout.width) + "x" + std::to_string(layout.height) + ":" + type +
         (layout.bigEndian ? ":be" : ":le");
}

Result<HeightEncoding> parseHeightEncoding(std::string_view text) {
  for (HeightEncoding encoding :
       {HeightEncoding::Auto, HeightEncoding::Greyscale, HeightEncoding::TerrainRgb, HeightEncoding::Terrarium})
    if (text == heightEncodingName(encoding)) return encoding;
  return makeError(ErrorKind::InvalidArgument,
                   "height encoding '" + std::string(text) + "' is not one of auto, greyscale, terrain-rgb, terrarium");
}

const char* heightEncodingName(HeightEncoding encoding) {
  switch (encoding) {
    case HeightEncoding::Auto:
      return "auto";
    case HeightEncoding::Greyscale:
      return "greyscale";
    case HeightEncoding::TerrainRgb:
      return "terrain-rgb";
    case HeightEncoding::Terrarium:
      return "terrarium";
  }
  return "unknown";
}

}  // namespace polder::terrain
