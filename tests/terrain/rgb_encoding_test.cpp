#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include <polder/terrain/rgb_encoding.hpp>

namespace polder::terrain {
namespace {

void encodeTerrainRgb(double metres, std::uint8_t* p) {
  const auto value = std::uint32_t(std::lround((metres + 10000.0) * 10.0));
  p[0] = std::uint8_t(value >> 16), p[1] = std::uint8_t(value >> 8), p[2] = std::uint8_t(value);
}

void encodeTerrarium(double metres, std::uint8_t* p) {
  const double value = metres + 32768.0;
  p[0] = std::uint8_t(int(value) / 256), p[1] = std::uint8_t(int(value) % 256);
  p[2] = std::uint8_t(std::lround((value - std::floor(value)) * 256.0));
}

// A hilly surface between about lowM and highM, north row first, as a tile stores it.
double hill(int x, int y, double lowM, double highM) {
  return lowM + (highM - lowM) * 0.5 * (1.0 + std::sin(x * 0.05) * std::cos(y * 0.07));
}

std::vector<std::uint8_t> tile(int size, int channels, bool terrainRgb, double lowM, double highM) {
  std::vector<std::uint8_t> pixels(std::size_t(size * size * channels), 255);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      std::uint8_t* p = &pixels[std::size_t((y * size + x) * channels)];
      terrainRgb ? encodeTerrainRgb(hill(x, y, lowM, highM), p) : encodeTerrarium(hill(x, y, lowM, highM), p);
    }
  return pixels;
}

TEST(RgbEncoding, DocumentedFormulas) {
  EXPECT_DOUBLE_EQ(decodeTerrainRgb(0, 0, 0), -10000.0);
  EXPECT_NEAR(decodeTerrainRgb(1, 134, 160), 0.0, 1e-9);  // 100000 * 0.1 - 10000
  EXPECT_NEAR(decodeTerrainRgb(255, 255, 255), 1667721.5, 1e-6);
  EXPECT_DOUBLE_EQ(decodeTerrarium(128, 0, 0), 0.0);
  EXPECT_DOUBLE_EQ(decodeTerrarium(0, 0, 0), -32768.0);
  EXPECT_DOUBLE_EQ(decodeTerrarium(128, 1, 128), 1.5);
  EXPECT_DOUBLE_EQ(decodeTerrarium(155, 200, 64), 155 * 256 + 200 + 0.25 - 32768);
}

TEST(RgbEncoding, DecodesAndFlips) {
  // 2 x 2 RGBA, north row first: 100 m, 200 m / 300 m, transparent.
  std::vector<std::uint8_t> pixels(16, 255);
  encodeTerrainRgb(100.0, &pixels[0]);
  encodeTerrainRgb(200.0, &pixels[4]);
  encodeTerrainRgb(300.0, &pixels[8]);
  pixels[15] = 0;
  const RgbView view{pixels.data(), 2, 2, 4};
  const Heightfield field = decodeRgbHeights(view, HeightEncoding::TerrainRgb, true);
  EXPECT_NEAR(field.at(0, 1), 100.0f, 1e-3);
  EXPECT_NEAR(field.at(1, 1), 200.0f, 1e-3);
  EXPECT_NEAR(field.at(0, 0), 300.0f, 1e-3);
  EXPECT_TRUE(std::isnan(field.at(1, 0)));
  EXPECT_FALSE(std::isnan(decodeRgbHeights(view, HeightEncoding::TerrainRgb, false).at(1, 0)));

  std::vector<std::uint8_t> rgb(3);
  encodeTerrarium(-42.25, rgb.data());
  EXPECT_FLOAT_EQ(decodeRgbHeights({rgb.data(), 1, 1, 3}, HeightEncoding::Terrarium, true).at(0, 0), -42.25f);
}

TEST(RgbEncoding, DetectsTerrainRgb) {
  for (auto [low, high] : {std::pair{0.0, 3800.0}, std::pair{-400.0, 50.0}, std::pair{-10000.0, 8800.0}}) {
    const auto pixels = tile(64, 3, true, low, high);
    const auto detected = detectRgbEncoding({pixels.data(), 64, 64, 3});
    ASSERT_TRUE(detected.ok()) << detected.error().message;
    EXPECT_EQ(*detected, HeightEncoding::TerrainRgb) << low << ".." << high;
  }
}

TEST(RgbEncoding, DetectsTerrarium) {
  for (auto [low, high] : {std::pair{0.0, 3800.0}, std::pair{-1.0, 7188.0}, std::pair{-10900.0, 8800.0}}) {
    const auto pixels = tile(64, 4, false, low, high);
    const auto detected = detectRgbEncoding({pixels.data(), 64, 64, 4});
    ASSERT_TRUE(detected.ok()) << detected.error().message;
    EXPECT_EQ(*detected, HeightEncoding::Terrarium) << low << ".." << high;
  }
}

TEST(RgbEncoding, GreyImagesSavedAsRgbAreGreyscale) {
  std::vector<std::uint8_t> pixels(32 * 32 * 3);
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = std::uint8_t((i / 3) % 251);
  const auto detected = detectRgbEncoding({pixels.data(), 32, 32, 3});
  ASSERT_TRUE(detected.ok());
  EXPECT_EQ(*detected, HeightEncoding::Greyscale);
}

TEST(RgbEncoding, TransparentPixelsDoNotSpoilDetection) {
  auto pixels = tile(32, 4, false, 100.0, 900.0);
  for (int i = 0; i < 32 * 10; ++i) {  // the top 10 rows transparent black
    pixels[std::size_t(i * 4)] = pixels[std::size_t(i * 4 + 1)] = pixels[std::size_t(i * 4 + 2)] = 0;
    pixels[std::size_t(i * 4 + 3)] = 0;
  }
  const auto detected = detectRgbEncoding({pixels.data(), 32, 32, 4});
  ASSERT_TRUE(detected.ok()) << detected.error().message;
  EXPECT_EQ(*detected, HeightEncoding::Terrarium);
}

TEST(RgbEncoding, ImplausibleColoursAreAnError) {
  // Saturated colours: R = 200 is beyond Terrarium's 9 km and Terrain-RGB's too.
  std::vector<std::uint8_t> pixels(16 * 16 * 3);
  for (std::size_t i = 0; i < pixels.size(); i += 3)
    pixels[i] = 200, pixels[i + 1] = std::uint8_t(i), pixels[i + 2] = 30;
  const auto detected = detectRgbEncoding({pixels.data(), 16, 16, 3});
  ASSERT_FALSE(detected.ok());
  EXPECT_EQ(detected.error().kind, ErrorKind::InvalidData);
  EXPECT_NE(detected.error().message.find("neither Terrain-RGB"), std::string::npos) << detected.error().message;
}

}  // namespace
}  // namespace polder::terrain
