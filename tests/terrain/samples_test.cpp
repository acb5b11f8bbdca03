#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include <polder/terrain/samples.hpp>

namespace polder::terrain {
namespace {

template <class T>
SampleSource sourceOf(const std::vector<T>& values, SampleFormat format, int width, int height, int channels = 1) {
  SampleSource source;
  source.data = reinterpret_cast<const std::byte*>(values.data());
  source.format = format;
  source.width = width;
  source.height = height;
  source.channels = channels;
  return source;
}

TEST(DecodeSamples, FlipsNorthRowFirstToSouthRowFirst) {
  // 3 x 2, the file's first row (north) is 1 2 3.
  const std::vector<std::uint16_t> stored = {1, 2, 3, 4, 5, 6};
  const auto field = decodeSamples(sourceOf(stored, SampleFormat::U16, 3, 2), {});
  ASSERT_TRUE(field.ok());
  EXPECT_EQ(field->width, 3);
  EXPECT_EQ(field->height, 2);
  EXPECT_EQ(field->at(0, 0), 4.0f);  // south-west
  EXPECT_EQ(field->at(2, 0), 6.0f);
  EXPECT_EQ(field->at(0, 1), 1.0f);  // north-west
  EXPECT_EQ(field->at(2, 1), 3.0f);
}

TEST(DecodeSamples, AppliesScaleAndOffset) {
  const std::vector<std::uint8_t> stored = {0, 10, 255, 100};
  SampleDecoding decoding;
  decoding.scale = 0.5;
  decoding.offset = -20.0;
  const auto field = decodeSamples(sourceOf(stored, SampleFormat::U8, 2, 2), decoding);
  ASSERT_TRUE(field.ok());
  EXPECT_FLOAT_EQ(field->at(0, 1), -20.0f);
  EXPECT_FLOAT_EQ(field->at(1, 1), -15.0f);
  EXPECT_FLOAT_EQ(field->at(0, 0), 107.5f);
  EXPECT_FLOAT_EQ(field->at(1, 0), 30.0f);
}

TEST(DecodeSamples, PicksOneChannelOfInterleavedPixels) {
  const std::vector<std::int32_t> stored = {1, -100, 2, -200, 3, -300, 4, -400};
  SampleSource source = sourceOf(stored, SampleFormat::I32, 2, 2, 2);
  source.channel = 1;
  const auto field = decodeSamples(source, {});
  ASSERT_TRUE(field.ok());
  EXPECT_EQ(field->at(0, 1), -100.0f);
  EXPECT_EQ(field->at(1, 0), -400.0f);
}

TEST(DecodeSamples, SwapsByteOrder) {
  std::vector<std::uint8_t> bytes = {0x01, 0x02, 0xff, 0xfe};  // int16 258 and -2 stored swapped
  const std::int16_t probe = 1;
  const bool little = *reinterpret_cast<const std::uint8_t*>(&probe) == 1;
  SampleSource source = sourceOf(bytes, SampleFormat::I16, 2, 1);
  source.swapBytes = little;  // the bytes above are big-endian
  const auto field = decodeSamples(source, {});
  ASSERT_TRUE(field.ok());
  EXPECT_EQ(field->at(0, 0), 258.0f);
  EXPECT_EQ(field->at(1, 0), -2.0f);

  const std::vector<double> wide = {1.5, -2.25};
  std::vector<std::uint8_t> swapped(16);
  for (int i = 0; i < 2; ++i) {
    std::uint8_t b[8];
    std::memcpy(b, &wide[std::size_t(i)], 8);
    for (int k = 0; k < 8; ++k) swapped[std::size_t(i * 8 + k)] = b[7 - k];
  }
  SampleSource doubles = sourceOf(swapped, SampleFormat::F64, 2, 1);
  doubles.swapBytes = true;
  const auto decoded = decodeSamples(doubles, {});
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded->at(0, 0), 1.5f);
  EXPECT_EQ(decoded->at(1, 0), -2.25f);
}

TEST(DecodeSamples, MarksVoidsAsNaN) {
  const std::vector<std::int16_t> stored = {-32768, -32767, -32766, -9999, 0, 100};
  SampleDecoding decoding;
  decoding.int16Voids = true;
  decoding.nodata = -9999.0;
  const auto field = decodeSamples(sourceOf(stored, SampleFormat::I16, 3, 2), decoding);
  ASSERT_TRUE(field.ok());
  EXPECT_TRUE(std::isnan(field->at(0, 1)));
  EXPECT_TRUE(std::isnan(field->at(1, 1)));
  EXPECT_EQ(field->at(2, 1), -32766.0f);
  EXPECT_TRUE(std::isnan(field->at(0, 0)));
  EXPECT_EQ(field->at(1, 0), 0.0f);

  // Without the rules nothing is a void.
  const auto plain = decodeSamples(sourceOf(stored, SampleFormat::I16, 3, 2), {});
  ASSERT_TRUE(plain.ok());
  for (float h : plain->heights) EXPECT_FALSE(std::isnan(h));
  EXPECT_EQ(plain->at(0, 1), -32768.0f);
}

TEST(DecodeSamples, Int16VoidRuleOnlyForInt16) {
  const std::vector<float> stored = {-32768.0f, 5.0f};
  SampleDecoding decoding;
  decoding.int16Voids = true;
  const auto field = decodeSamples(sourceOf(stored, SampleFormat::F32, 2, 1), decoding);
  ASSERT_TRUE(field.ok());
  EXPECT_EQ(field->at(0, 0), -32768.0f);
}

TEST(DecodeSamples, FloatNodataMatchesInFloatPrecision) {
  // GDAL writes a float raster's no-data as the double closest to the float.
  const std::vector<float> stored = {-3.4028234663852886e+38f, 12.0f};
  SampleDecoding decoding;
  decoding.nodata = -3.4028234663852886e+38;
  const auto field = decodeSamples(sourceOf(stored, SampleFormat::F32, 2, 1), decoding);
  ASSERT_TRUE(field.ok());
  EXPECT_TRUE(std::isnan(field->at(0, 0)));
  EXPECT_EQ(field->at(1, 0), 12.0f);
}

TEST(DecodeSamples, NaNIsAVoidOnlyWhenTheNodataIsNaN) {
  const std::vector<float> stored = {1.0f, std::numeric_limits<float>::quiet_NaN()};
  SampleDecoding decoding;
  decoding.nodata = std::numeric_limits<double>::quiet_NaN();
  const auto field = decodeSamples(sourceOf(stored, SampleFormat::F32, 2, 1), decoding);
  ASSERT_TRUE(field.ok());
  EXPECT_TRUE(std::isnan(field->at(1, 0)));
}

TEST(DecodeSamples, RejectsNaNAndInfinityNamingTheSample) {
  std::vector<float> stored(12, 1.0f);
  stored[7] = std::numeric_limits<float>::quiet_NaN();  // column 3, row 1 from the north
  auto field = decodeSamples(sourceOf(stored, SampleFormat::F32, 4, 3), {});
  ASSERT_FALSE(field.ok());
  EXPECT_EQ(field.error().kind, ErrorKind::InvalidData);
  EXPECT_NE(field.error().message.find("NaN"), std::string::npos) << field.error().message;
  EXPECT_NE(field.error().message.find("column 3, row 1"), std::string::npos) << field.error().message;

  stored[7] = 1.0f;
  stored[0] = -std::numeric_limits<float>::infinity();
  field = decodeSamples(sourceOf(stored, SampleFormat::F32, 4, 3), {});
  ASSERT_FALSE(field.ok());
  EXPECT_NE(field.error().message.find("infinite"), std::string::npos) << field.error().message;

  const std::vector<double> huge = {1e300};
  field = decodeSamples(sourceOf(huge, SampleFormat::F64, 1, 1), {});
  ASSERT_FALSE(field.ok());
  EXPECT_NE(field.error().message.find("out of range"), std::string::npos) << field.error().message;
}

TEST(SampleFormat, SizesAndNames) {
  EXPECT_EQ(sampleFormatBytes(SampleFormat::U8), 1u);
  EXPECT_EQ(sampleFormatBytes(SampleFormat::I16), 2u);
  EXPECT_EQ(sampleFormatBytes(SampleFormat::F32), 4u);
  EXPECT_EQ(sampleFormatBytes(SampleFormat::F64), 8u);
  EXPECT_STREQ(sampleFormatName(SampleFormat::U16), "uint16");
  EXPECT_STREQ(sampleFormatName(SampleFormat::F32), "float32");
}

}  // namespace
}  // namespace polder::terrain
