#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include <polder/terrain/hgt.hpp>

#include "wgs84_reference.hpp"

namespace polder::terrain {
namespace {

using test::metresPerDegreeLatitude;
using test::metresPerDegreeLongitude;

// A tile of `size`^2 big-endian samples, north row first: height = 10 * row + column % 7.
std::vector<std::byte> makeTile(int size) {
  std::vector<std::byte> bytes(std::size_t(size) * std::size_t(size) * 2);
  for (int row = 0; row < size; ++row)
    for (int x = 0; x < size; ++x) {
      const auto value = std::uint16_t(std::int16_t(10 * row + x % 7));
      const std::size_t i = (std::size_t(row) * std::size_t(size) + std::size_t(x)) * 2;
      bytes[i] = std::byte(value >> 8);
      bytes[i + 1] = std::byte(value & 0xff);
    }
  return bytes;
}

void setSample(std::vector<std::byte>& bytes, int size, int x, int row, std::int16_t value) {
  const std::size_t i = (std::size_t(row) * std::size_t(size) + std::size_t(x)) * 2;
  bytes[i] = std::byte(std::uint16_t(value) >> 8);
  bytes[i + 1] = std::byte(std::uint16_t(value) & 0xff);
}

TEST(Hgt, SizeFromLength) {
  EXPECT_EQ(hgtSizeFromLength(2884802), 1201);
  EXPECT_EQ(hgtSizeFromLength(25934402), 3601);
  EXPECT_EQ(hgtSizeFromLength(2884800), 0);
  EXPECT_EQ(hgtSizeFromLength(0), 0);
  EXPECT_TRUE(checkHgtLength(2884802).ok());
  const Status bad = checkHgtLength(1000);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().kind, ErrorKind::InvalidData);
  EXPECT_NE(bad.error().message.find("1000"), std::string::npos);
}

TEST(Hgt, LatitudeFromName) {
  EXPECT_EQ(hgtSouthLatitude("N46W122.hgt"), 46);
  EXPECT_EQ(hgtSouthLatitude("s12e130.HGT"), -12);
  EXPECT_EQ(hgtSouthLatitude("/data/srtm/N00E006.hgt"), 0);
  EXPECT_EQ(hgtSouthLatitude("rainier.hgt"), std::nullopt);
  EXPECT_EQ(hgtSouthLatitude("N9W1.hgt"), std::nullopt);
  EXPECT_EQ(hgtSouthLatitude("N91W000.hgt"), std::nullopt);
  EXPECT_EQ(hgtSouthLatitude(""), std::nullopt);
}

TEST(Hgt, Decodes1201TileWithVoidFlipAndSpacing) {
  std::vector<std::byte> bytes = makeTile(1201);
  setSample(bytes, 1201, 500, 600, -32768);  // a void
  const auto dem = decodeHgt(bytes, "N46W122.hgt", {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  const Heightfield& field = dem->field;
  EXPECT_EQ(field.width, 1201);
  EXPECT_EQ(field.height, 1201);
  // File row 0 (north) holds 0..6; it becomes the last row.
  EXPECT_EQ(field.at(3, 1200), 3.0f);
  EXPECT_EQ(field.at(3, 0), 12003.0f);
  EXPECT_EQ(dem->info.voids, 1);
  // The void at file row 600, column 500 is filled from its neighbours (~6002).
  EXPECT_NEAR(field.at(500, 1200 - 600), 6000.0 + 500 % 7, 4.0);
  EXPECT_EQ(dem->info.format, "hgt");
  EXPECT_EQ(dem->info.encoding, "int16");
  EXPECT_FALSE(dem->info.spacingAssumed);
  EXPECT_NEAR(field.spacingY, metresPerDegreeLatitude(46.5) * 3.0 / 3600.0, 0.01);   // ~92.63
  EXPECT_NEAR(field.spacingX, metresPerDegreeLongitude(46.5) * 3.0 / 3600.0, 0.01);  // ~63.97
  EXPECT_FLOAT_EQ(dem->info.minM, 0.0f);
  EXPECT_FLOAT_EQ(dem->info.maxM, 12006.0f);
}

TEST(Hgt, OneArcSecondTileSouthernHemisphere) {
  const auto dem = decodeHgt(makeTile(3601), "S34E151.hgt", {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->field.width, 3601);
  EXPECT_NEAR(dem->field.spacingY, metresPerDegreeLatitude(-33.5) / 3600.0, 0.01);
  EXPECT_NEAR(dem->field.spacingX, metresPerDegreeLongitude(-33.5) / 3600.0, 0.01);
  EXPECT_EQ(dem->info.voids, 0);
}

TEST(Hgt, OptionsAndUnnamedTiles) {
  std::vector<std::byte> bytes = makeTile(1201);
  setSample(bytes, 1201, 0, 0, -32767);
  DemOptions options;
  options.nodataEnabled = false;
  options.spacingM = 30.0;
  options.zScale = 2.0;
  auto dem = decodeHgt(bytes, "N46W122.hgt", options);
  ASSERT_TRUE(dem.ok());
  EXPECT_EQ(dem->info.voids, 0);
  EXPECT_EQ(dem->field.at(0, 1200), -65534.0f);
  EXPECT_EQ(dem->field.spacingX, 30.0);
  EXPECT_EQ(dem->field.spacingY, 30.0);

  dem = decodeHgt(bytes, "mountain.hgt", {});
  ASSERT_TRUE(dem.ok());
  EXPECT_TRUE(dem->info.spacingAssumed);
  EXPECT_EQ(dem->field.spacingX, 1.0);
}

TEST(Hgt, RejectsBadInput) {
  std::vector<std::byte> bytes = makeTile(1201);
  auto dem = decodeHgt(std::span<const std::byte>(bytes).first(bytes.size() - 2), "N46W122.hgt", {});
  ASSERT_FALSE(dem.ok());
  EXPECT_EQ(dem.error().kind, ErrorKind::InvalidData);
  EXPECT_NE(dem.error().message.find("2884800"), std::string::npos) << dem.error().message;

  for (std::size_t i = 0; i < bytes.size(); i += 2) bytes[i] = std::byte(0x80), bytes[i + 1] = std::byte(0);
  dem = decodeHgt(bytes, "N46W122.hgt", {});
  ASSERT_FALSE(dem.ok());
  EXPECT_EQ(dem.error().kind, ErrorKind::InvalidData);
  EXPECT_NE(dem.error().message.find("no-data"), std::string::npos) << dem.error().message;

  DemOptions options;
  options.encoding = HeightEncoding::Terrarium;
  dem = decodeHgt(makeTile(1201), "N46W122.hgt", options);
  ASSERT_FALSE(dem.ok());
  EXPECT_EQ(dem.error().kind, ErrorKind::InvalidArgument);
}

}  // namespace
}  // namespace polder::terrain
