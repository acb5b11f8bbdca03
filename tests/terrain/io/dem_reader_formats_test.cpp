// readDem on every format, with files the tests make.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <polder/terrain/dem_reader.hpp>

#include "dem_test_files.hpp"
#include "test_support.hpp"

namespace polder::terrain {
namespace {

using test::ScratchDir;
using test::writeImage;

// 5 x 3 samples, north row first: row r, column c holds 100 * r + 10 * c + base.
template <class T>
std::vector<T> ramp(int width, int height, double base, double step = 1.0) {
  std::vector<T> values;
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c) values.push_back(T(base + step * (100.0 * r + 10.0 * c)));
  return values;
}

// The file's north row first is the Heightfield's last row.
template <class T>
void expectFlipped(const Heightfield& field, const std::vector<T>& fileValues, double scale = 1.0,
                   double tolerance = 0.0) {
  ASSERT_EQ(field.sampleCount(), fileValues.size());
  for (int r = 0; r < field.height; ++r)
    for (int c = 0; c < field.width; ++c)
      ASSERT_NEAR(field.at(c, field.height - 1 - r), double(fileValues[std::size_t(r * field.width + c)]) * scale,
                  tolerance + 1e-4)
          << "file column " << c << " row " << r;
}

TEST(ReadDem, Png8Greyscale) {
  ScratchDir dir;
  const auto values = ramp<std::uint8_t>(5, 3, 3.0, 0.5);
  writeImage(dir.file("grey8.png"), 5, 3, 1, values);
  const auto dem = readDem(dir.file("grey8.png"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->field.width, 5);
  EXPECT_EQ(dem->field.height, 3);
  expectFlipped(dem->field, values);
  EXPECT_EQ(dem->field.at(0, 2), 3.0f);  // the file's first sample is the north-west corner
  EXPECT_EQ(dem->info.format, "png");
  EXPECT_EQ(dem->info.encoding, "uint8");
  EXPECT_EQ(dem->info.path, dir.file("grey8.png").string());
  EXPECT_TRUE(dem->info.spacingAssumed);
  EXPECT_EQ(dem->field.spacingX, 1.0);
  EXPECT_EQ(dem->info.minM, 3.0);
  EXPECT_EQ(dem->info.maxM, 3.0 + 0.5 * 240.0);
}

TEST(ReadDem, Png16WithSpacingAndScale) {
  ScratchDir dir;
  const auto values = ramp<std::uint16_t>(5, 3, 40000.0, 10.0);
  writeImage(dir.file("grey16.png"), 5, 3, 1, values);
  DemOptions options;
  options.spacingM = 160.0;
  options.zScale = 0.1;
  const auto dem = readDem(dir.file("grey16.png"), options);
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  expectFlipped(dem->field, values, 0.1, 1e-3);
  EXPECT_EQ(dem->info.encoding, "uint16");
  EXPECT_FALSE(dem->info.spacingAssumed);
  EXPECT_EQ(dem->field.spacingX, 160.0);
  EXPECT_EQ(dem->field.spacingY, 160.0);
  EXPECT_NEAR(dem->info.maxM, 4240.0, 1e-3);
}

TEST(ReadDem, TiffSampleTypes) {
  ScratchDir dir;
  const auto i16 = ramp<std::int16_t>(5, 3, -400.0, 3.0);
  const auto u16 = ramp<std::uint16_t>(5, 3, 60000.0, 2.0);
  const auto f32 = ramp<float>(5, 3, -12.25, 0.125);
  writeImage(dir.file("i16.tif"), 5, 3, 1, i16);
  writeImage(dir.file("u16.tif"), 5, 3, 1, u16);
  writeImage(dir.file("f32.tif"), 5, 3, 1, f32);

  auto dem = readDem(dir.file("i16.tif"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  expectFlipped(dem->field, i16);
  EXPECT_EQ(dem->info.format, "tiff");
  EXPECT_EQ(dem->info.encoding, "int16");
  EXPECT_EQ(dem->info.minM, -400.0);

  dem = readDem(dir.file("u16.tif"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  expectFlipped(dem->field, u16);  // no normalisation to 0..1
  EXPECT_EQ(dem->info.encoding, "uint16");
  EXPECT_EQ(dem->info.maxM, 60000.0 + 2.0 * 240.0);

  dem = readDem(dir.file("f32.tif"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  expectFlipped(dem->field, f32);
  EXPECT_EQ(dem->info.encoding, "float32");
}

TEST(ReadDem, TiledAndCompressedTiffs) {
  ScratchDir dir;
  const auto i16 = ramp<std::int16_t>(100, 70, -1000.0, 0.5);  // not a multiple of the tile
  const auto f32 = ramp<float>(100, 70, 3.5, 0.01);
  writeImage(dir.file("i16_zip.tif"), 100, 70, 1, i16, {32, "zip"});
  writeImage(dir.file("f32_lzw.tif"), 100, 70, 1, f32, {16, "lzw"});
  {
    auto in = OIIO::ImageInput::open(dir.file("i16_zip.tif").string());
    ASSERT_TRUE(in);
    ASSERT_EQ(in->spec().tile_width, 32);  // the test really makes a tiled, compressed file
    ASSERT_EQ(in->spec().get_string_attribute("compression"), "zip");
  }
  auto dem = readDem(dir.file("i16_zip.tif"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  expectFlipped(dem->field, i16);
  dem = readDem(dir.file("f32_lzw.tif"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  expectFlipped(dem->field, f32);
}

TEST(ReadDem, Int16VoidsAreFilledUnlessNodataIsOff) {
  ScratchDir dir;
  auto values = ramp<std::int16_t>(20, 20, 100.0);
  values[5 * 20 + 7] = -32768;
  values[12 * 20 + 3] = -32767;
  writeImage(dir.file("voids.tif"), 20, 20, 1, values, {16, "zip"});
  auto dem = readDem(dir.file("voids.tif"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->info.voids, 2);
  EXPECT_NEAR(dem->field.at(7, 19 - 5), 100.0 + 500.0 + 70.0, 15.0);  // between its neighbours
  EXPECT_EQ(dem->info.minM, 100.0);

  DemOptions options;
  options.nodataEnabled = false;
  dem = readDem(dir.file("voids.tif"), options);
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->info.voids, 0);
  EXPECT_EQ(dem->info.minM, -32768.0);
}

TEST(ReadDem, OpenExrFloatAndHalf) {
  ScratchDir dir;
  const auto f32 = ramp<float>(6, 4, -8.5, 0.75);
  writeImage(dir.file("f32.exr"), 6, 4, 1, f32);
  std::vector<std::uint16_t> halves(f32.size());
  OIIO::convert_pixel_values(OIIO::TypeDesc::FLOAT, f32.data(), OIIO::TypeDesc::HALF, halves.data(), int(f32.size()));
  writeImage(dir.file("f16.exr"), 6, 4, 1, OIIO::TypeDesc::HALF, halves.data());

  auto dem = readDem(dir.file("f32.exr"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  expectFlipped(dem->field, f32);
  EXPECT_EQ(dem->info.format, "openexr");
  EXPECT_EQ(dem->info.encoding, "float32");

  dem = readDem(dir.file("f16.exr"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  expectFlipped(dem->field, f32, 1.0, 0.5);  // half keeps ~3 significant digits
  EXPECT_EQ(dem->info.encoding, "float16");
}

// North row first: heights 100 * row + 10 * column + base.
std::vector<std::uint8_t> rgbTile(int width, int height, int channels, bool terrainRgb, double base) {
  std::vector<std::uint8_t> pixels;
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c) {
      const double h = base + 100.0 * r + 10.0 * c;
      if (terrainRgb) {
        const auto v = std::uint32_t(std::lround((h + 10000.0) * 10.0));
        pixels.insert(pixels.end(), {std::uint8_t(v >> 16), std::uint8_t(v >> 8), std::uint8_t(v)});
      } else {
        const double v = h + 32768.0;
        pixels.insert(pixels.end(), {std::uint8_t(int(v) / 256), std::uint8_t(int(v) % 256),
                                     std::uint8_t(std::lround((v - std::floor(v)) * 256.0))});
      }
      if (channels == 4) pixels.push_back(255);
    }
  return pixels;
}

TEST(ReadDem, TerrainRgbAndTerrariumAutoDetected) {
  ScratchDir dir;
  writeImage(dir.file("terrain_rgb.png"), 8, 6, 4, rgbTile(8, 6, 4, true, 250.3));
  writeImage(dir.file("terrarium.png"), 8, 6, 3, rgbTile(8, 6, 3, false, -120.5));

  auto dem = readDem(dir.file("terrain_rgb.png"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->info.encoding, "terrain-rgb");
  EXPECT_NEAR(dem->field.at(0, 5), 250.3, 0.06);  // north-west
  EXPECT_NEAR(dem->field.at(7, 0), 250.3 + 500.0 + 70.0, 0.06);
  EXPECT_NEAR(dem->info.minM, 250.3, 0.06);

  dem = readDem(dir.file("terrarium.png"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->info.encoding, "terrarium");
  EXPECT_NEAR(dem->field.at(0, 5), -120.5, 0.01);
  EXPECT_NEAR(dem->info.maxM, -120.5 + 570.0, 0.01);
  EXPECT_TRUE(dem->info.spacingAssumed);
}

TEST(ReadDem, ExplicitRgbEncodingsAndGreyscaleOverride) {
  ScratchDir dir;
  writeImage(dir.file("tile.png"), 8, 6, 3, rgbTile(8, 6, 3, false, 1000.0));
  DemOptions options;
  options.encoding = HeightEncoding::Terrarium;
  auto dem = readDem(dir.file("tile.png"), options);
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_NEAR(dem->field.at(0, 5), 1000.0, 0.01);

  options.encoding = HeightEncoding::TerrainRgb;  // wrong, but asked for: decoded as told
  dem = readDem(dir.file("tile.png"), options);
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_GT(dem->info.minM, 100000.0);

  options.encoding = HeightEncoding::Greyscale;  // the red channel as heights
  dem = readDem(dir.file("tile.png"), options);
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->field.at(0, 5), float((1000 + 32768) / 256));
  EXPECT_EQ(dem->info.encoding, "uint8");
}

TEST(ReadDem, TransparentTilePixelsAreVoids) {
  ScratchDir dir;
  auto pixels = rgbTile(8, 6, 4, true, 50.0);
  pixels[(2 * 8 + 3) * 4 + 3] = 0;
  writeImage(dir.file("holes.png"), 8, 6, 4, pixels);
  auto dem = readDem(dir.file("holes.png"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->info.voids, 1);
  EXPECT_NEAR(dem->field.at(3, 5 - 2), 50.0 + 200.0 + 30.0, 10.0);
  DemOptions options;
  options.nodataEnabled = false;
  dem = readDem(dir.file("holes.png"), options);
  ASSERT_TRUE(dem.ok());
  EXPECT_EQ(dem->info.voids, 0);
}

TEST(ReadDem, GreyImageSavedAsRgbReadsAsGreyscale) {
  ScratchDir dir;
  std::vector<std::uint8_t> pixels;
  for (int i = 0; i < 12; ++i)
    pixels.insert(pixels.end(), {std::uint8_t(i * 20), std::uint8_t(i * 20), std::uint8_t(i * 20)});
  writeImage(dir.file("grey_rgb.png"), 4, 3, 3, pixels);
  const auto dem = readDem(dir.file("grey_rgb.png"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->info.encoding, "uint8");
  EXPECT_EQ(dem->field.at(3, 0), 220.0f);
}

TEST(ReadDem, SrtmHgtWithVoid) {
  ScratchDir dir;
  std::vector<std::int16_t> values(1201 * 1201);
  for (int r = 0; r < 1201; ++r)
    for (int c = 0; c < 1201; ++c) values[std::size_t(r * 1201 + c)] = std::int16_t(4000 - 3 * r + c % 5);
  values[600 * 1201 + 600] = -32768;
  test::writeFile(dir.file("N46W122.hgt"), test::storeSamples(values, true));
  const auto dem = readDem(dir.file("N46W122.hgt"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->field.width, 1201);
  EXPECT_EQ(dem->info.format, "hgt");
  EXPECT_EQ(dem->info.voids, 1);
  EXPECT_EQ(dem->field.at(0, 1200), 4000.0f);  // north-west sample
  EXPECT_EQ(dem->field.at(0, 0), 4000.0f - 3600.0f);
  EXPECT_NEAR(dem->field.at(600, 600), 4000.0 - 1800.0 + 0.0, 3.0);
  EXPECT_NEAR(dem->field.spacingY, test::metresPerDegreeLatitude(46.5) / 1200.0, 0.01);
  EXPECT_NEAR(dem->field.spacingX, test::metresPerDegreeLongitude(46.5) / 1200.0, 0.01);
}

TEST(ReadDem, RawFilesInEveryLayout) {
  ScratchDir dir;
  const auto u16 = ramp<std::uint16_t>(5, 3, 1000.0);
  const auto i16 = ramp<std::int16_t>(5, 3, -300.0);
  const auto f32 = ramp<float>(5, 3, 0.5, 0.25);
  for (bool bigEndian : {false, true}) {
    const std::string order = bigEndian ? ":be" : ":le";
    test::writeFile(dir.file("h.r16"), test::storeSamples(u16, bigEndian));
    test::writeFile(dir.file("h.raw"), test::storeSamples(i16, bigEndian));
    test::writeFile(dir.file("h.f32"), test::storeSamples(f32, bigEndian));
    DemOptions options;
    options.raw = RawLayout{5, 3, SampleType::U16, bigEndian};
    auto dem = readDem(dir.file("h.r16"), options);
    ASSERT_TRUE(dem.ok()) << dem.error().message;
    expectFlipped(dem->field, u16);
    EXPECT_EQ(dem->info.format, "raw");

    options.raw = RawLayout{5, 3, SampleType::I16, bigEndian};
    dem = readDem(dir.file("h.raw"), options);
    ASSERT_TRUE(dem.ok()) << dem.error().message;
    expectFlipped(dem->field, i16);

    options.raw = RawLayout{5, 3, SampleType::F32, bigEndian};
    options.zScale = 2.0;
    dem = readDem(dir.file("h.f32"), options);
    ASSERT_TRUE(dem.ok()) << dem.error().message;
    expectFlipped(dem->field, f32, 2.0);
    EXPECT_EQ(dem->info.encoding, "float32");
  }
}

TEST(ReadDem, ContentDecidesOverTheExtension) {
  ScratchDir dir;
  const auto values = ramp<std::uint16_t>(5, 3, 7.0);
  writeImage(dir.file("height.png"), 5, 3, 1, values);
  std::filesystem::rename(dir.file("height.png"), dir.file("height.dat"));
  const auto dem = readDem(dir.file("height.dat"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->info.format, "png");
  expectFlipped(dem->field, values);
}

}  // namespace
}  // namespace polder::terrain
