#include <polder/terrain/samples.hpp>

#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>

namespace polder::terrain {
namespace {

template <class T>
T loadSample(const std::byte* at, bool swapBytes) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, at, sizeof(T));
  if (swapBytes)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

std::string sampleName(int column, int rowFromNorth) {
  return "sample (column " + std::to_string(column) + ", row " + std::to_string(rowFromNorth) + " from the north)";
}

template <class T>
Result<Heightfield> decodeTyped(const SampleSource& source, const SampleDecoding& decoding) {
  Heightfield field(source.width, source.height);
  const std::size_t pixelBytes = sizeof(T) * std::size_t(source.channels);
  const std::size_t rowBytes = pixelBytes * std::size_t(source.width);
  const bool nanIsVoid = decoding.nodata && std::isnan(*decoding.nodata);
  // Compare in the stored type's precision: GDAL writes a float's no-data as its double text.
  const bool hasNodata = decoding.nodata && !nanIsVoid;
  const double nodata = !hasNodata                 ? 0.0
                        : std::is_same_v<T, float> ? double(float(*decoding.nodata))
                                                   : *decoding.nodata;
  const bool int16Voids = decoding.int16Voids && std::is_same_v<T, std::int16_t>;
  constexpr float kVoid = std::numeric_limits<float>::quiet_NaN();
  constexpr double kFloatMax = std::numeric_limits<float>::max();

  const auto isVoid = [&](double stored) {
    return (hasNodata && stored == nodata) | (int16Voids && stored <= -32767.0) | (nanIsVoid && stored != stored);
  };
  const auto storedAt = [&](int x, int row) {
    return double(loadSample<T>(source.data + std::size_t(row) * rowBytes + pixelBytes * std::size_t(x) +
                                    sizeof(T) * std::size_t(source.channel),
                                source.swapBytes));
  };

  for (int row = 0; row < source.height; ++row) {
    float* out = field.heights.data() + std::size_t(source.height - 1 - row) * std::size_t(source.width);
    bool bad = false;
    // Branch-free on the common path: this loop runs over every sample of every DEM.
    for (int x = 0; x < source.width; ++x) {
      const double stored = storedAt(x, row);
      const double metres = decoding.offset + stored * decoding.scale;
      const bool isVoidSample = isVoid(stored);
      bad |= !isVoidSample & !(std::abs(metres) <= kFloatMax);  // NaN, infinite or beyond float
      out[x] = isVoidSample ? kVoid : float(metres);
    }
    for (int x = 0; bad && x < source.width; ++x) {  // rare: find and name the culprit
      const double stored = storedAt(x, row);
      if (isVoid(stored)) continue;
      if (std::isnan(stored))
        return makeError(ErrorKind::InvalidData, sampleName(x, row) + " is NaN and no no-data value says it is a void");
      if (std::isinf(stored)) return makeError(ErrorKind::InvalidData, sampleName(x, row) + " is infinite");
      if (!(std::abs(decoding.offset + stored * decoding.scale) <= kFloatMax))
        return makeError(ErrorKind::InvalidData, sampleName(x, row) + " = " + std::to_string(stored) +
                                                     " is out of range once scaled to metres");
    }
  }
  return field;
}

}  // namespace

std::size_t sampleFormatBytes(SampleFormat format) {
  switch (format) {
    case SampleFormat::U8:
      return 1;
    case SampleFormat::U16:
    case SampleFormat::I16:
      return 2;
    case SampleFormat::U32:
    case SampleFormat::I32:
    case SampleFormat::F32:
      return 4;
    case SampleFormat::F64:
      return 8;
  }
  return 0;
}

const char* sampleFormatName(SampleFormat format) {
  switch (format) {
    case SampleFormat::U8:
      return "uint8";
    case SampleFormat::U16:
      return "uint16";
    case SampleFormat::I16:
      return "int16";
    case SampleFormat::U32:
      return "uint32";
    case SampleFormat::I32:
      return "int32";
    case SampleFormat::F32:
      return "float32";
    case SampleFormat::F64:
      return "float64";
  }
  return "unknown";
}

Result<Heightfield> decodeSamples(const SampleSource& source, const SampleDecoding& decoding) {
  assert(source.data && source.width > 0 && source.height > 0 && "decodeSamples: empty source");
  assert(source.channel >= 0 && source.channel < source.channels && "decodeSamples: channel out of range");
  switch (source.format) {
    case SampleFormat::U8:
      return decodeTyped<std::uint8_t>(source, decoding);
    case SampleFormat::U16:
      return decodeTyped<std::uint16_t>(source, decoding);
    case SampleFormat::I16:
      return decodeTyped<std::int16_t>(source, decoding);
    case SampleFormat::U32:
      return decodeTyped<std::uint32_t>(source, decoding);
    case SampleFormat::I32:
      return decodeTyped<std::int32_t>(source, decoding);
    case SampleFormat::F32:
      return decodeTyped<float>(source, decoding);
    case SampleFormat::F64:
      return decodeTyped<double>(source, decoding);
  }
  return makeError(ErrorKind::Unsupported, "unknown sample format");
}

}  // namespace polder::terrain
