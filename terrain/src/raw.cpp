#include <polder/terrain/raw.hpp>

#include <bit>
#include <string>

#include <polder/terrain/dem_parsing.hpp>
#include <polder/terrain/dem_validation.hpp>
#include <polder/terrain/samples.hpp>

namespace polder::terrain {
namespace {

SampleFormat sampleFormat(SampleType type) {
  switch (type) {
    case SampleType::U16:
      return SampleFormat::U16;
    case SampleType::I16:
      return SampleFormat::I16;
    case SampleType::F32:
      return SampleFormat::F32;
  }
  return SampleFormat::U16;
}

}  // namespace

std::uint64_t rawByteSize(const RawLayout& layout) {
  if (layout.width <= 0 || layout.height <= 0) return 0;
  return std::uint64_t(layout.width) * std::uint64_t(layout.height) * sampleFormatBytes(sampleFormat(layout.type));
}

Result<Dem> decodeRaw(std::span<const std::byte> bytes, const RawLayout& layout, const DemOptions& options) {
  if (Status valid = checkDemOptions(options); !valid) return valid.error();
  const SampleFormat format = sampleFormat(layout.type);
  const std::string described = rawLayoutName(layout);
  const std::uint64_t expected = rawByteSize(layout);
  if (expected == 0) return makeError(ErrorKind::InvalidArgument, "raw layout " + described + " has no samples");
  if (bytes.size() != expected)
    return makeError(ErrorKind::InvalidData, "raw layout " + described + " needs " + std::to_string(expected) +
                                                 " bytes but the file has " + std::to_string(bytes.size()));
  if (options.encoding == HeightEncoding::TerrainRgb || options.encoding == HeightEncoding::Terrarium)
    return makeError(ErrorKind::InvalidArgument,
                     "a raw file holds one height per sample; the encoding option does not apply");

  SampleSource source;
  source.data = bytes.data();
  source.format = format;
  source.width = layout.width;
  source.height = layout.height;
  source.swapBytes = layout.bigEndian != (std::endian::native == std::endian::big);
  SampleDecoding decoding;
  decoding.scale = options.zScale;
  decoding.int16Voids = options.nodataEnabled;
  auto field = decodeSamples(source, decoding);
  if (!field) return field.error();
  DemInfo info;
  info.format = "raw";
  info.encoding = sampleFormatName(format);
  return finishDem(std::move(*field), std::move(info), options, std::nullopt);
}

}  // namespace polder::terrain
