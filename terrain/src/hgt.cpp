#include <polder/terrain/hgt.hpp>

#include <bit>
#include <cctype>
#include <charconv>
#include <string>

#include <polder/terrain/dem_validation.hpp>
#include <polder/terrain/samples.hpp>

namespace polder::terrain {

int hgtSizeFromLength(std::uint64_t bytes) {
  for (int size : {1201, 3601})
    if (bytes == 2 * std::uint64_t(size) * std::uint64_t(size)) return size;
  return 0;
}

Status checkHgtLength(std::uint64_t bytes) {
  if (hgtSizeFromLength(bytes) != 0) return {};
  return makeError(
      ErrorKind::InvalidData,
      "an SRTM .hgt tile has 2884802 (1201^2) or 25934402 (3601^2) bytes, this one " + std::to_string(bytes));
}

std::optional<int> hgtSouthLatitude(std::string_view fileName) {
  const std::size_t slash = fileName.find_last_of("/\\");
  if (slash != std::string_view::npos) fileName.remove_prefix(slash + 1);
  if (fileName.size() < 3) return std::nullopt;
  const char hemisphere = char(std::toupper(static_cast<unsigned char>(fileName[0])));
  if (hemisphere != 'N' && hemisphere != 'S') return std::nullopt;
  if (!std::isdigit(static_cast<unsigned char>(fileName[1])) || !std::isdigit(static_cast<unsigned char>(fileName[2])))
    return std::nullopt;
  const int degrees = (fileName[1] - '0') * 10 + (fileName[2] - '0');
  if (degrees > 90) return std::nullopt;
  return hemisphere == 'N' ? degrees : -degrees;
}

Result<Dem> decodeHgt(std::span<const std::byte> bytes, std::string_view fileName, const DemOptions& options) {
  if (Status valid = checkDemOptions(options); !valid) return valid.error();
  if (Status length = checkHgtLength(bytes.size()); !length) return length.error();
  const int size = hgtSizeFromLength(bytes.size());
  if (options.encoding == HeightEncoding::TerrainRgb || options.encoding == HeightEncoding::Terrarium)
    return makeError(ErrorKind::InvalidArgument,
                     "an SRTM .hgt tile holds int16 heights; the encoding option does not apply");

  SampleSource source;
  source.data = bytes.data();
  source.format = SampleFormat::I16;
  source.width = source.height = size;
  source.swapBytes = std::endian::native != std::endian::big;
  SampleDecoding decoding;
  decoding.scale = options.zScale;
  decoding.int16Voids = options.nodataEnabled;
  auto field = decodeSamples(source, decoding);
  if (!field) return field.error();

  std::optional<GroundSpacing> spacing;
  if (const auto south = hgtSouthLatitude(fileName)) {
    const double arcDegrees = (size == 1201 ? 3.0 : 1.0) / 3600.0;
    const GroundSpacing perDegree = metresPerDegree(*south + 0.5);
    spacing = GroundSpacing{arcDegrees * perDegree.x, arcDegrees * perDegree.y};
  }
  DemInfo info;
  info.format = "hgt";
  info.encoding = "int16";
  return finishDem(std::move(*field), std::move(info), options, spacing);
}

}  // namespace polder::terrain
