// The writers round-trip through readDem with no options.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <polder/terrain/dem_reader.hpp>
#include <polder/terrain/image_writer.hpp>

#include "dem_test_files.hpp"
#include "test_support.hpp"

namespace polder::terrain {
namespace {

using test::ScratchDir;

Heightfield terrain(int width, int height, double spacingX, double spacingY) {
  Heightfield field(width, height, spacingX, spacingY);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      field.at(x, y) = float(-35.5 + 1200.0 * std::sin(x * 0.07) * std::cos(y * 0.05) + y);
  return field;
}

TEST(WriteHeightPng16, RoundTripsSpacingAndMetres) {
  ScratchDir dir;
  const Heightfield field = terrain(70, 45, 12.5, 17.25);
  ASSERT_TRUE(writeHeightPng16(dir.file("gen.png"), field).ok());
  const auto dem = readDem(dir.file("gen.png"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->field.width, 70);
  EXPECT_EQ(dem->field.height, 45);
  EXPECT_EQ(dem->field.spacingX, 12.5);
  EXPECT_EQ(dem->field.spacingY, 17.25);
  EXPECT_FALSE(dem->info.spacingAssumed);
  const HeightQuantization q = fitHeightQuantization(field);
  for (std::size_t i = 0; i < field.heights.size(); ++i)
    ASSERT_NEAR(dem->field.heights[i], field.heights[i], q.metresPerUnit * 0.5 + 1e-3) << i;
  EXPECT_NEAR(dem->info.minM, q.offsetM, 1e-3);
  // The file is an ordinary 16-bit greyscale PNG, north row first.
  auto in = OIIO::ImageInput::open(dir.file("gen.png").string());
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().format, OIIO::TypeDesc::UINT16);
  EXPECT_EQ(in->spec().nchannels, 1);
  std::vector<std::uint16_t> raw(70 * 45);
  ASSERT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::UINT16, raw.data()));
  const auto lowest = std::min_element(field.heights.begin(), field.heights.end()) - field.heights.begin();
  const int lowX = int(lowest % 70), lowY = int(lowest / 70);
  EXPECT_EQ(raw[std::size_t((44 - lowY) * 70 + lowX)], 0);
}

TEST(WriteHeightPng16, ExplicitQuantizationAndRange) {
  ScratchDir dir;
  Heightfield field(3, 2, 2.0, 2.0);
  field.heights = {0.0f, 0.1f, 6553.5f, 100.0f, 200.3f, 0.5f};
  ASSERT_TRUE(writeHeightPng16(dir.file("tenths.png"), field, HeightQuantization{0.1, 0.0}).ok());
  const auto dem = readDem(dir.file("tenths.png"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(dem->field.heights[i], field.heights[i], 1e-3);

  // zScale other than 1 replaces the file's own mapping.
  DemOptions options;
  options.zScale = 1.0 / 8.0;
  const auto scaled = readDem(dir.file("tenths.png"), options);
  ASSERT_TRUE(scaled.ok());
  EXPECT_NEAR(scaled->info.maxM, 65535.0 / 8.0, 1e-3);

  field.heights[0] = -1.0f;  // below the offset
  const Status status = writeHeightPng16(dir.file("bad.png"), field, HeightQuantization{0.1, 0.0});
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().kind, ErrorKind::InvalidArgument);
  EXPECT_NE(status.error().message.find("does not fit 16 bits"), std::string::npos) << status.error().message;
  EXPECT_NE(status.error().message.find("bad.png"), std::string::npos);
}

TEST(WriteHeightTiffFloat, RoundTripsExactly) {
  ScratchDir dir;
  const Heightfield field = terrain(53, 31, 30.0, 45.5);
  ASSERT_TRUE(writeHeightTiffFloat(dir.file("gen.tif"), field).ok());
  const auto dem = readDem(dir.file("gen.tif"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->info.format, "geotiff");
  EXPECT_EQ(dem->info.encoding, "float32");
  EXPECT_EQ(dem->field.spacingX, 30.0);
  EXPECT_EQ(dem->field.spacingY, 45.5);
  EXPECT_EQ(dem->field.heights, field.heights);
}

TEST(WriteHeightFiles, RefuseBadFieldsAndPaths) {
  ScratchDir dir;
  Heightfield field(4, 4, 1.0, 1.0);
  field.heights[5] = std::numeric_limits<float>::quiet_NaN();
  for (const auto& status :
       {writeHeightPng16(dir.file("nan.png"), field), writeHeightTiffFloat(dir.file("nan.tif"), field)}) {
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error().kind, ErrorKind::InvalidArgument);
    EXPECT_NE(status.error().message.find("not finite"), std::string::npos) << status.error().message;
  }
  EXPECT_FALSE(writeHeightPng16(dir.file("empty.png"), Heightfield()).ok());
  EXPECT_FALSE(writeHeightTiffFloat(dir.file("empty.tif"), Heightfield()).ok());

  const Heightfield good(4, 4, 1.0, 1.0);
  const auto missing = dir.path() / "no" / "such" / "folder";
  for (const auto& status : {writeHeightPng16(missing / "a.png", good), writeHeightTiffFloat(missing / "a.tif", good),
                             writeRgbaPng(missing / "a.png", RgbaImage(2, 2))}) {
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error().kind, ErrorKind::Io);
    EXPECT_NE(status.error().message.find(missing.string()), std::string::npos) << status.error().message;
    EXPECT_EQ(status.error().message.find('\n'), std::string::npos);
  }
}

TEST(WriteRgbaPng, RoundTripsPixelsTopRowFirst) {
  ScratchDir dir;
  RgbaImage image(7, 5);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 7; ++x) {
      std::uint8_t* p = image.at(x, y);
      p[0] = std::uint8_t(x * 30), p[1] = std::uint8_t(y * 50), p[2] = 77, p[3] = std::uint8_t(x == 3 ? 0 : 255 - y);
    }
  ASSERT_TRUE(writeRgbaPng(dir.file("frame.png"), image).ok());
  auto in = OIIO::ImageInput::open(dir.file("frame.png").string());
  ASSERT_TRUE(in);
  ASSERT_EQ(in->spec().nchannels, 4);
  in.reset();
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  in = OIIO::ImageInput::open(dir.file("frame.png").string(), &config);
  std::vector<std::uint8_t> pixels(7 * 5 * 4);
  ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, pixels.data()));
  EXPECT_EQ(pixels, image.pixels);  // straight alpha, not premultiplied

  RgbaImage broken(3, 3);
  broken.pixels.resize(5);
  const Status status = writeRgbaPng(dir.file("broken.png"), broken);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().kind, ErrorKind::InvalidArgument);
}

}  // namespace
}  // namespace polder::terrain
