#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include <polder/terrain/raw.hpp>

#include "sample_bytes.hpp"

namespace polder::terrain {
namespace {

// Values stored north row first, in the byte order asked for.
template <class T>
std::vector<std::byte> store(const std::vector<T>& values, bool bigEndian) {
  const std::string bytes = test::storeSamples(values, bigEndian);
  std::vector<std::byte> out(bytes.size());
  std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

RawLayout layout(int width, int height, SampleType type, bool bigEndian) {
  return RawLayout{width, height, type, bigEndian};
}

TEST(Raw, ByteSize) {
  EXPECT_EQ(rawByteSize(layout(3, 2, SampleType::U16, false)), 12u);
  EXPECT_EQ(rawByteSize(layout(3, 2, SampleType::F32, true)), 24u);
  EXPECT_EQ(rawByteSize(layout(0, 2, SampleType::F32, true)), 0u);
}

TEST(Raw, U16BothByteOrders) {
  const std::vector<std::uint16_t> values = {1, 2, 3, 60000, 5, 6};
  for (bool bigEndian : {false, true}) {
    const auto dem = decodeRaw(store(values, bigEndian), layout(3, 2, SampleType::U16, bigEndian), {});
    ASSERT_TRUE(dem.ok()) << dem.error().message;
    EXPECT_EQ(dem->field.at(0, 1), 1.0f) << bigEndian;  // north row first in the file
    EXPECT_EQ(dem->field.at(0, 0), 60000.0f) << bigEndian;
    EXPECT_EQ(dem->info.format, "raw");
    EXPECT_EQ(dem->info.encoding, "uint16");
    EXPECT_TRUE(dem->info.spacingAssumed);
    EXPECT_EQ(dem->info.voids, 0);
  }
}

TEST(Raw, I16VoidsBothByteOrders) {
  const std::vector<std::int16_t> values = {-5, -32768, 7, 9};
  for (bool bigEndian : {false, true}) {
    const auto dem = decodeRaw(store(values, bigEndian), layout(2, 2, SampleType::I16, bigEndian), {});
    ASSERT_TRUE(dem.ok()) << dem.error().message;
    EXPECT_EQ(dem->info.voids, 1);
    EXPECT_EQ(dem->field.at(0, 1), -5.0f);
    EXPECT_EQ(dem->field.at(1, 0), 9.0f);
    EXPECT_GE(dem->field.at(1, 1), -5.0f);  // filled within the valid range
    EXPECT_LE(dem->field.at(1, 1), 9.0f);
    EXPECT_EQ(dem->info.minM, -5.0);
  }
}

TEST(Raw, F32BothByteOrdersWithOptions) {
  const std::vector<float> values = {0.5f, -1.25f, 1000.0f, 3.0f};
  DemOptions options;
  options.zScale = 0.5;
  options.spacingM = 12.5;
  for (bool bigEndian : {false, true}) {
    const auto dem = decodeRaw(store(values, bigEndian), layout(2, 2, SampleType::F32, bigEndian), options);
    ASSERT_TRUE(dem.ok()) << dem.error().message;
    EXPECT_EQ(dem->field.at(1, 1), -0.625f);
    EXPECT_EQ(dem->field.at(0, 0), 500.0f);
    EXPECT_EQ(dem->field.spacingX, 12.5);
    EXPECT_EQ(dem->field.spacingY, 12.5);
    EXPECT_FALSE(dem->info.spacingAssumed);
    EXPECT_EQ(dem->info.encoding, "float32");
  }
}

TEST(Raw, RejectsSizeMismatchAndNaN) {
  const std::vector<std::uint16_t> values(10, 1);
  auto dem = decodeRaw(store(values, false), layout(3, 3, SampleType::U16, false), {});
  ASSERT_FALSE(dem.ok());
  EXPECT_EQ(dem.error().kind, ErrorKind::InvalidData);
  EXPECT_NE(dem.error().message.find("3x3:u16:le needs 18 bytes but the file has 20"), std::string::npos)
      << dem.error().message;

  const std::vector<float> withNaN = {1.0f, NAN, 2.0f, 3.0f};
  dem = decodeRaw(store(withNaN, false), layout(2, 2, SampleType::F32, false), {});
  ASSERT_FALSE(dem.ok());
  EXPECT_NE(dem.error().message.find("NaN"), std::string::npos);

  DemOptions bad;
  bad.zScale = 0.0;
  dem = decodeRaw(store(values, false), layout(5, 2, SampleType::U16, false), bad);
  ASSERT_FALSE(dem.ok());
  EXPECT_EQ(dem.error().kind, ErrorKind::InvalidArgument);
}

}  // namespace
}  // namespace polder::terrain
