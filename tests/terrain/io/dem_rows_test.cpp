// openDemRows against readDem on every format the reader tests make: the same heights in
// bands of any size (voids apart: filled along rows here), the same header, errors naming
// the file, and a raster far larger than memory read a few bands at a time.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <polder/terrain/dem_reader.hpp>
#include <polder/terrain/dem_rows.hpp>
#include <polder/terrain/image_writer.hpp>

#include "dem_test_files.hpp"
#include "test_support.hpp"

namespace polder::terrain {
namespace {

using test::ScratchDir;
using test::writeImage;

// North row first: row r, column c holds base + step * (100 r + 10 c).
template <class T>
std::vector<T> ramp(int width, int height, double base, double step = 1.0) {
  std::vector<T> values;
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c) values.push_back(T(base + step * (100.0 * r + 10.0 * c)));
  return values;
}

// Every row, `band` rows per call, south to north (or north to south).
std::vector<float> readAll(DemRows& rows, int band, bool northFirst = false) {
  std::vector<float> heights(std::size_t(rows.width()) * std::size_t(rows.height()));
  for (int i = 0; i < rows.height(); i += band) {
    const int count = std::min(band, rows.height() - i);
    const int y0 = northFirst ? rows.height() - i - count : i;
    const std::span<float> out(heights.data() + std::size_t(y0) * std::size_t(rows.width()),
                               std::size_t(count) * std::size_t(rows.width()));
    const Status read = rows.readRows(y0, count, out);
    EXPECT_TRUE(read.ok()) << read.error().message;
    if (!read) break;
  }
  return heights;
}

// The rows equal readDem's heights in bands of 1, 7 and all rows (voids may differ: at most
// `voids` samples, the count readDem gives); the header matches. Returns the rows' heights.
std::vector<float> expectSameAsReadDem(const std::filesystem::path& path, const DemOptions& options = {},
                                       bool streamed = true) {
  const auto dem = readDem(path, options);
  EXPECT_TRUE(dem.ok()) << dem.error().message;
  auto rows = openDemRows(path, options);
  EXPECT_TRUE(rows.ok()) << rows.error().message;
  if (!dem || !rows) return {};
  DemRows& source = **rows;
  EXPECT_EQ(source.width(), dem->field.width);
  EXPECT_EQ(source.height(), dem->field.height);
  EXPECT_EQ(source.spacingX(), dem->field.spacingX);
  EXPECT_EQ(source.spacingY(), dem->field.spacingY);
  EXPECT_EQ(source.info().path, dem->info.path);
  EXPECT_EQ(source.info().format, dem->info.format);
  EXPECT_EQ(source.info().encoding, dem->info.encoding);
  EXPECT_EQ(source.info().spacingAssumed, dem->info.spacingAssumed);
  EXPECT_EQ(source.streamed(), streamed) << path;
  std::vector<float> heights;
  for (const int band : {1, 7, source.height()}) {
    for (const bool northFirst : {false, true}) {
      heights = readAll(source, band, northFirst);
      std::int64_t differing = 0;
      for (std::size_t i = 0; i < heights.size(); ++i) {
        EXPECT_TRUE(std::isfinite(heights[i])) << i;
        differing += heights[i] != dem->field.heights[i];
      }
      EXPECT_LE(differing, dem->info.voids) << path << " in bands of " << band;
    }
    EXPECT_EQ(source.info().voids, dem->info.voids) << "voids of distinct rows, counted once";
  }
  return heights;
}

TEST(DemRows, GreyscalePngs) {
  ScratchDir dir;
  writeImage(dir.file("grey8.png"), 37, 29, 1, ramp<std::uint8_t>(37, 29, 3.0, 0.05));
  expectSameAsReadDem(dir.file("grey8.png"));
  writeImage(dir.file("grey16.png"), 37, 29, 1, ramp<std::uint16_t>(37, 29, 40000.0, 3.0));
  DemOptions options;
  options.spacingM = 160.0;
  options.zScale = 0.1;
  expectSameAsReadDem(dir.file("grey16.png"), options);

  // A Polder PNG carries its spacing and its mapping to metres.
  Heightfield field(33, 21, 12.5, 7.0);
  for (std::size_t i = 0; i < field.heights.size(); ++i) field.heights[i] = -50.0f + 0.37f * float(i % 97);
  ASSERT_TRUE(writeHeightPng16(dir.file("polder.png"), field).ok());
  expectSameAsReadDem(dir.file("polder.png"));
}

TEST(DemRows, StripedTiffsOfEverySampleType) {
  ScratchDir dir;
  writeImage(dir.file("i16.tif"), 100, 70, 1, ramp<std::int16_t>(100, 70, -400.0, 3.0));
  writeImage(dir.file("u16.tif"), 100, 70, 1, ramp<std::uint16_t>(100, 70, 30000.0, 2.0));
  writeImage(dir.file("f32.tif"), 100, 70, 1, ramp<float>(100, 70, -12.25, 0.125));
  writeImage(dir.file("u8_zip.tif"), 100, 70, 1, ramp<std::uint8_t>(100, 70, 1.0, 0.03), {0, "zip"});
  {
    auto in = OIIO::ImageInput::open(dir.file("u8_zip.tif").string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().tile_width, 0);
    const int rowsPerStrip = in->spec().get_int_attribute("tiff:RowsPerStrip", 0);
    EXPECT_TRUE(rowsPerStrip > 1 && rowsPerStrip < 70) << "several strips of several rows: " << rowsPerStrip;
  }
  for (const char* name : {"i16.tif", "u16.tif", "f32.tif", "u8_zip.tif"}) expectSameAsReadDem(dir.file(name));
}

TEST(DemRows, TiledTiffsAndGeoTiffs) {
  ScratchDir dir;
  writeImage(dir.file("i16_zip.tif"), 100, 70, 1, ramp<std::int16_t>(100, 70, -1000.0, 0.5), {32, "zip"});
  writeImage(dir.file("f32_lzw.tif"), 100, 70, 1, ramp<float>(100, 70, 3.5, 0.01), {16, "lzw"});
  {
    auto in = OIIO::ImageInput::open(dir.file("i16_zip.tif").string());
    ASSERT_TRUE(in);
    ASSERT_EQ(in->spec().tile_height, 32);  // really tiled, and 70 rows end inside a tile
  }
  expectSameAsReadDem(dir.file("i16_zip.tif"));
  expectSameAsReadDem(dir.file("f32_lzw.tif"));

  std::vector<std::int16_t> hills;
  for (int r = 0; r < 30; ++r)
    for (int c = 0; c < 40; ++c) hills.push_back(std::int16_t(500 + 7 * r - 3 * c));
  test::GeoTags tags;
  tags.pixelScale = {25.0, 30.0, 0.0};
  tags.tiepoint = {0, 0, 0, 500000.0, 5200000.0, 0};
  tags.geoKeys = test::geoKeyDirectory({{1024, 1}, {1025, 1}, {3072, 32610}});
  test::writeGeoTiff(dir.file("utm_tiled.tif"), 40, 30, hills, tags, true);
  test::writeGeoTiff(dir.file("utm_strip.tif"), 40, 30, hills, tags, false);
  expectSameAsReadDem(dir.file("utm_tiled.tif"));
  expectSameAsReadDem(dir.file("utm_strip.tif"));
  DemOptions options;
  options.spacingM = 2.0;
  expectSameAsReadDem(dir.file("utm_tiled.tif"), options);
}

// An uncompressed float TIFF whose tiles are `tileWidth` x 1, written byte by byte: libtiff
// writes tile lengths in multiples of 16 only, but reads any.
std::string tiffOfOneRowTiles(int width, int height, int tileWidth, const std::vector<float>& northFirst) {
  using test::littleEndian;
  const std::uint32_t across = std::uint32_t((width + tileWidth - 1) / tileWidth),
                      tiles = across * std::uint32_t(height);
  const std::uint32_t tileBytes = std::uint32_t(tileWidth) * 4, dataStart = 8;
  const std::uint32_t offsets = dataStart + tiles * tileBytes, counts = offsets + 4 * tiles;
  std::string bytes = "II*" + std::string(1, '\0') + littleEndian(counts + 4 * tiles, 4);  // the directory, last
  for (int row = 0; row < height; ++row)
    for (int column = 0; column < int(across) * tileWidth; ++column) {
      std::uint32_t bits;
      std::memcpy(&bits, &northFirst[std::size_t(row) * std::size_t(width) + std::size_t(std::min(column, width - 1))],
                  4);
      bytes += littleEndian(bits, 4);
    }
  for (std::uint32_t t = 0; t < tiles; ++t) bytes += littleEndian(dataStart + t * tileBytes, 4);
  for (std::uint32_t t = 0; t < tiles; ++t) bytes += littleEndian(tileBytes, 4);
  return bytes + test::tiffDirectory({{256, 3, 1, std::uint32_t(width)},
                                      {257, 3, 1, std::uint32_t(height)},
                                      {258, 3, 1, 32},  // bits per sample
                                      {259, 3, 1, 1},   // no compression
                                      {262, 3, 1, 1},   // black is zero
                                      {277, 3, 1, 1},   // samples per pixel
                                      {284, 3, 1, 1},   // contiguous
                                      {322, 3, 1, std::uint32_t(tileWidth)},
                                      {323, 3, 1, 1},
                                      {324, 4, tiles, offsets},
                                      {325, 4, tiles, counts},
                                      {339, 3, 1, 3}});  // IEEE float
}

TEST(DemRows, TilesOneRowHigh) {
  // Read as tiles, a band of one row at a time: OpenImageIO's scanline path divides by zero
  // on such tiles (found by fuzzing).
  ScratchDir dir;
  std::vector<float> hills;
  for (int r = 0; r < 17; ++r)
    for (int c = 0; c < 23; ++c) hills.push_back(100.0f + 1.5f * float(r) - 0.25f * float(c * c));
  std::vector<float> southFirst;
  for (int r = 16; r >= 0; --r)
    southFirst.insert(southFirst.end(), hills.begin() + r * 23, hills.begin() + r * 23 + 23);
  TIFFErrorHandler quiet = TIFFSetWarningHandler(nullptr);  // "nonstandard tile length"
  for (const int tileWidth : {256, 16, 32}) {
    SCOPED_TRACE(tileWidth);
    const auto file = dir.file("tiles_" + std::to_string(tileWidth) + "x1.tif");
    test::writeFile(file, tiffOfOneRowTiles(23, 17, tileWidth, hills));
    {
      auto in = OIIO::ImageInput::open(file.string());
      ASSERT_TRUE(in) << OIIO::geterror();
      ASSERT_EQ(in->spec().tile_height, 1);
    }
    EXPECT_EQ(expectSameAsReadDem(file), southFirst);
  }
  TIFFSetWarningHandler(quiet);
}

TEST(DemRows, OpenExr) {
  ScratchDir dir;
  const auto f32 = ramp<float>(36, 20, -8.5, 0.75);
  writeImage(dir.file("f32.exr"), 36, 20, 1, f32);
  writeImage(dir.file("f32_tiled.exr"), 36, 20, 1, f32, {16, ""});
  std::vector<std::uint16_t> halves(f32.size());
  OIIO::convert_pixel_values(OIIO::TypeDesc::FLOAT, f32.data(), OIIO::TypeDesc::HALF, halves.data(), int(f32.size()));
  writeImage(dir.file("f16.exr"), 36, 20, 1, OIIO::TypeDesc::HALF, halves.data());
  for (const char* name : {"f32.exr", "f32_tiled.exr", "f16.exr"}) expectSameAsReadDem(dir.file(name));
}

// North row first: heights 100 * row + 10 * column + base, as Terrain-RGB or Terrarium.
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

TEST(DemRows, RgbEncodedTilesByRowsOnceTheEncodingIsKnown) {
  ScratchDir dir;
  auto rgba = rgbTile(24, 18, 4, true, 250.3);
  rgba[(2 * 24 + 3) * 4 + 3] = 0;  // a transparent pixel: a void
  writeImage(dir.file("terrain_rgb.png"), 24, 18, 4, rgba);
  writeImage(dir.file("terrarium.png"), 24, 18, 3, rgbTile(24, 18, 3, false, -120.5));

  // Detecting the encoding needs every pixel: read whole, with readDem's void filling.
  expectSameAsReadDem(dir.file("terrain_rgb.png"), {}, false);
  expectSameAsReadDem(dir.file("terrarium.png"), {}, false);

  DemOptions options;
  options.encoding = HeightEncoding::TerrainRgb;
  const auto filled = expectSameAsReadDem(dir.file("terrain_rgb.png"), options);
  ASSERT_FALSE(filled.empty());
  // The void, file row 2 column 3, lies between its row's neighbours.
  const std::size_t at = std::size_t(17 - 2) * 24 + 3;
  EXPECT_NEAR(filled[at], 250.3 + 200.0 + 30.0, 0.06);
  options.encoding = HeightEncoding::Terrarium;
  expectSameAsReadDem(dir.file("terrarium.png"), options);
  options.encoding = HeightEncoding::Greyscale;
  expectSameAsReadDem(dir.file("terrarium.png"), options);

  // Too large to read whole for the memory it may take: the message says what to do.
  DemOptions small;
  small.memoryLimitBytes = 1000;
  const auto refused = openDemRows(dir.file("terrarium.png"), small);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(int(refused.error().kind), int(ErrorKind::OutOfMemory));
  EXPECT_NE(refused.error().message.find(dir.file("terrarium.png").string()), std::string::npos);
  EXPECT_NE(refused.error().message.find("give the encoding"), std::string::npos) << refused.error().message;
}

TEST(DemRows, SrtmHgtAndRawInEveryLayout) {
  ScratchDir dir;
  std::vector<std::int16_t> values(1201 * 1201);
  for (int r = 0; r < 1201; ++r)
    for (int c = 0; c < 1201; ++c) values[std::size_t(r * 1201 + c)] = std::int16_t(4000 - 3 * r + c % 5);
  values[600 * 1201 + 600] = -32768;
  test::writeFile(dir.file("N46W122.hgt"), test::storeSamples(values, true));
  const auto heights = expectSameAsReadDem(dir.file("N46W122.hgt"));
  ASSERT_FALSE(heights.empty());
  // Between its row's neighbours 4000 - 1800 + (599 % 5) and + (601 % 5).
  EXPECT_EQ(heights[std::size_t(600) * 1201 + 600], 4000.0f - 1800.0f + 2.5f);

  const auto u16 = ramp<std::uint16_t>(15, 13, 1000.0);
  const auto i16 = ramp<std::int16_t>(15, 13, -300.0);
  const auto f32 = ramp<float>(15, 13, 0.5, 0.25);
  for (const bool bigEndian : {false, true}) {
    test::writeFile(dir.file("h.r16"), test::storeSamples(u16, bigEndian));
    test::writeFile(dir.file("h.raw"), test::storeSamples(i16, bigEndian));
    test::writeFile(dir.file("h.f32"), test::storeSamples(f32, bigEndian));
    DemOptions options;
    options.raw = RawLayout{15, 13, SampleType::U16, bigEndian};
    expectSameAsReadDem(dir.file("h.r16"), options);
    options.raw = RawLayout{15, 13, SampleType::I16, bigEndian};
    expectSameAsReadDem(dir.file("h.raw"), options);
    options.raw = RawLayout{15, 13, SampleType::F32, bigEndian};
    options.zScale = 2.0;
    options.spacingM = 3.0;
    expectSameAsReadDem(dir.file("h.f32"), options);
  }
}

TEST(DemRows, VoidsAreFilledAlongTheirRowWhateverTheBands) {
  ScratchDir dir;
  // 9 x 8, north row first; file row 1 has voids inside and at both ends, file row 4 and 5
  // have no valid sample at all.
  auto values = ramp<std::int16_t>(9, 8, 100.0);
  for (const int c : {0, 3, 4, 8}) values[std::size_t(1 * 9 + c)] = -32768;
  for (int c = 0; c < 9; ++c) values[std::size_t(4 * 9 + c)] = values[std::size_t(5 * 9 + c)] = -32767;
  writeImage(dir.file("voids.tif"), 9, 8, 1, values, {16, "zip"});
  auto rows = openDemRows(dir.file("voids.tif"), {});
  ASSERT_TRUE(rows.ok()) << rows.error().message;
  const auto once = readAll(**rows, 8);
  const auto row = [&](int fileRow) { return once.data() + std::size_t(7 - fileRow) * 9; };
  const auto stored = [&](int fileRow, int c) { return float(100 + 100 * fileRow + 10 * c); };
  EXPECT_EQ(row(1)[0], stored(1, 1));                                         // copied from the one side
  EXPECT_EQ(row(1)[3], stored(1, 2) + (stored(1, 5) - stored(1, 2)) / 3.0f);  // linear between
  EXPECT_EQ(row(1)[8], stored(1, 7));
  for (int c = 0; c < 9; ++c) {
    EXPECT_EQ(row(4)[c], stored(3, c)) << "from the nearest valid row, file row 3";
    EXPECT_EQ(row(5)[c], stored(6, c)) << "from the nearest valid row, file row 6";
  }
  EXPECT_EQ((*rows)->info().voids, 4 + 18);

  for (const int band : {1, 2, 3, 7}) {
    auto again = openDemRows(dir.file("voids.tif"), {});
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(readAll(**again, band), once) << "bands of " << band;
    EXPECT_EQ(readAll(**again, band, true), once) << "bands of " << band << ", north first";
    EXPECT_EQ((*again)->info().voids, 4 + 18);
  }
  // One row alone, its valid neighbours never read before.
  auto alone = openDemRows(dir.file("voids.tif"), {});
  ASSERT_TRUE(alone.ok());
  std::vector<float> one(9);
  ASSERT_TRUE((*alone)->readRows(7 - 5, 1, one).ok());
  EXPECT_EQ(std::vector<float>(row(5), row(5) + 9), one);

  std::vector<std::int16_t> allVoids(10 * 10, -32768);
  writeImage(dir.file("all_voids.tif"), 10, 10, 1, allVoids);
  auto empty = openDemRows(dir.file("all_voids.tif"), {});
  ASSERT_TRUE(empty.ok()) << "known only once rows are read";
  std::vector<float> band(30);
  const Status failed = (*empty)->readRows(0, 3, band);
  ASSERT_FALSE(failed.ok());
  EXPECT_EQ(int(failed.error().kind), int(ErrorKind::InvalidData));
  EXPECT_NE(failed.error().message.find("all_voids.tif: all 100 samples are no-data"), std::string::npos)
      << failed.error().message;
}

void expectError(const Status& status, ErrorKind kind, const std::filesystem::path& path, const std::string& problem) {
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(int(status.error().kind), int(kind)) << status.error().message;
  EXPECT_NE(status.error().message.find(path.string()), std::string::npos) << status.error().message;
  EXPECT_NE(status.error().message.find(problem), std::string::npos)
      << "expected '" << problem << "' in: " << status.error().message;
  EXPECT_EQ(status.error().message.find('\n'), std::string::npos);
}

template <class T>
Status statusOf(const Result<T>& result) {
  if (result) return {};
  return result.error();
}

TEST(DemRows, RowsOutsideTheRasterAreInvalidArguments) {
  ScratchDir dir;
  writeImage(dir.file("small.tif"), 6, 5, 1, ramp<std::uint16_t>(6, 5, 10.0));
  auto rows = openDemRows(dir.file("small.tif"), {});
  ASSERT_TRUE(rows.ok()) << rows.error().message;
  std::vector<float> out(12);
  const auto path = dir.file("small.tif");
  expectError((*rows)->readRows(-1, 2, out), ErrorKind::InvalidArgument, path, "outside");
  expectError((*rows)->readRows(4, 2, out), ErrorKind::InvalidArgument, path, "outside");
  expectError((*rows)->readRows(0, -2, out), ErrorKind::InvalidArgument, path, "outside");
  expectError((*rows)->readRows(0, 1, out), ErrorKind::InvalidArgument, path, "buffer");
  expectError((*rows)->readRows(std::numeric_limits<int>::max(), 2, out), ErrorKind::InvalidArgument, path, "outside");
  EXPECT_TRUE((*rows)->readRows(3, 2, out).ok()) << "still usable after bad requests";
  EXPECT_TRUE((*rows)->readRows(5, 0, std::span<float>()).ok());
}

TEST(DemRows, BadAndTruncatedFilesNameTheFile) {
  ScratchDir dir;
  expectError(statusOf(openDemRows(dir.file("missing.tif"), {})), ErrorKind::Io, dir.file("missing.tif"),
              "no such file");
  test::writeFile(dir.file("notes.txt"), "hello");
  expectError(statusOf(openDemRows(dir.file("notes.txt"), {})), ErrorKind::Unsupported, dir.file("notes.txt"),
              "unknown DEM format");

  // A tiled TIFF cut in half: found when opened, as readDem finds it.
  std::vector<std::int16_t> values(64 * 64, 7);
  writeImage(dir.file("tiled.tif"), 64, 64, 1, values, {16, "zip"});
  const std::string bytes = test::readBytes(dir.file("tiled.tif"));
  test::writeFile(dir.file("tiled_cut.tif"), bytes.substr(0, bytes.size() / 2));
  expectError(statusOf(openDemRows(dir.file("tiled_cut.tif"), {})), ErrorKind::InvalidData, dir.file("tiled_cut.tif"),
              "truncated TIFF: tile");

  // Raw and .hgt files of the wrong size.
  test::writeFile(dir.file("short.r16"), std::string(100, '\0'));
  DemOptions raw;
  raw.raw = RawLayout{8, 8, SampleType::U16, false};
  expectError(statusOf(openDemRows(dir.file("short.r16"), raw)), ErrorKind::InvalidData, dir.file("short.r16"),
              "needs 128 bytes but the file has 100");
  test::writeFile(dir.file("N00E000.hgt"), std::string(1000, '\0'));
  expectError(statusOf(openDemRows(dir.file("N00E000.hgt"), {})), ErrorKind::InvalidData, dir.file("N00E000.hgt"),
              "an SRTM .hgt tile has");

  // Cut short after it was opened: the rows that are gone fail, those still there read.
  test::writeFile(dir.file("cut.r16"), std::string(128, '\x01'));
  auto rows = openDemRows(dir.file("cut.r16"), raw);
  ASSERT_TRUE(rows.ok()) << rows.error().message;
  std::filesystem::resize_file(dir.file("cut.r16"), 64);  // the four north rows remain
  std::vector<float> band(16);
  EXPECT_TRUE((*rows)->readRows(6, 2, band).ok());
  expectError((*rows)->readRows(0, 2, band), ErrorKind::InvalidData, dir.file("cut.r16"), "truncated");

  // A NaN that no no-data value explains, named by its row in the file.
  std::vector<float> nan(8 * 8, 1.0f);
  nan[2 * 8 + 5] = std::numeric_limits<float>::quiet_NaN();
  writeImage(dir.file("nan.tif"), 8, 8, 1, nan);
  for (const int band : {1, 3, 8}) {
    auto opened = openDemRows(dir.file("nan.tif"), {});
    ASSERT_TRUE(opened.ok()) << opened.error().message;
    std::vector<float> out(8 * std::size_t(band));
    Status status;
    for (int y0 = 0; y0 < 8 && status.ok(); y0 += band)
      status = (*opened)->readRows(y0, std::min(band, 8 - y0),
                                   std::span(out).first(8 * std::size_t(std::min(band, 8 - y0))));
    expectError(status, ErrorKind::InvalidData, dir.file("nan.tif"), "(column 5, row 2 from the north) is NaN");
  }
}

// 70000^2 int16 samples: 9.8 GB on disk (sparse, so no disk is used) and 19.6 GB as floats,
// more than this test may take. Only the bands asked for are read.
TEST(DemRows, ARasterFarLargerThanMemoryIsReadABandAtATime) {
  ScratchDir dir;
  const int side = 70000;
  const std::uint64_t rowBytes = std::uint64_t(side) * 2;
  const auto path = dir.file("huge.raw");
  {
    std::ofstream out(path, std::ios::binary);
    ASSERT_TRUE(out);
  }
  std::filesystem::resize_file(path, rowBytes * std::uint64_t(side));
  // Marks in the north row (file row 0) and the south row (the last): column c holds c % 1000.
  {
    std::vector<std::int16_t> marks(static_cast<std::size_t>(side));
    for (int c = 0; c < side; ++c) marks[std::size_t(c)] = std::int16_t(c % 1000);
    std::fstream io(path, std::ios::binary | std::ios::in | std::ios::out);
    io.write(reinterpret_cast<const char*>(marks.data()), std::streamsize(rowBytes));
    for (auto& m : marks) m = std::int16_t(-m);
    io.seekp(std::streamoff(rowBytes * std::uint64_t(side - 1)));
    io.write(reinterpret_cast<const char*>(marks.data()), std::streamsize(rowBytes));
    ASSERT_TRUE(io.good());
  }
  DemOptions options;
  options.raw = RawLayout{side, side, SampleType::I16, false};
  options.spacingM = 30.0;
  EXPECT_EQ(int(readDem(path, options).error().kind), int(ErrorKind::OutOfMemory)) << "too large to read whole";

  auto rows = openDemRows(path, options);
  ASSERT_TRUE(rows.ok()) << rows.error().message;
  EXPECT_EQ((*rows)->width(), side);
  EXPECT_EQ((*rows)->height(), side);
  EXPECT_EQ((*rows)->spacingX(), 30.0);
  EXPECT_TRUE((*rows)->streamed());
  std::vector<float> band(std::size_t(7) * std::size_t(side));
  ASSERT_TRUE((*rows)->readRows(side - 7, 7, band).ok());  // the north edge last
  EXPECT_EQ(band[std::size_t(6) * std::size_t(side) + 12345], 345.0f);
  EXPECT_EQ(band[std::size_t(5) * std::size_t(side) + 12345], 0.0f);
  ASSERT_TRUE((*rows)->readRows(0, 7, band).ok());  // the south edge first
  EXPECT_EQ(band[std::size_t(side) - 1], -999.0f);
  EXPECT_EQ(band[std::size_t(side) + 1], 0.0f);
  std::vector<float> middle(std::size_t(256) * std::size_t(side));
  ASSERT_TRUE((*rows)->readRows(side / 2, 256, middle).ok());
  EXPECT_EQ(middle.front(), 0.0f);
  EXPECT_EQ((*rows)->info().voids, 0);

  rusage usage{};
  ASSERT_EQ(::getrusage(RUSAGE_SELF, &usage), 0);
  EXPECT_LT(double(usage.ru_maxrss) * 1024.0, 2.0 * double(1 << 30)) << "peak resident memory of this process";
}

// A real DEM from the shared data folder, skipped when absent.
TEST(DemRows, SharedSrtmGeoTiffWithVoidsMatchesReadDem) {
  POLDER_REQUIRE_SHARED_FILE(path, "dems/mt_rainier_90m_srtm3.tif");
  const auto heights = expectSameAsReadDem(path);
  // The voids are exactly the samples stored as -32768.
  DemOptions raw;
  raw.nodataEnabled = false;
  auto stored = openDemRows(path, raw);
  ASSERT_TRUE(stored.ok()) << stored.error().message;
  const auto values = readAll(**stored, 256);
  const auto dem = readDem(path, {});
  ASSERT_TRUE(dem.ok());
  std::int64_t voids = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i] == -32768.0f) {
      ++voids;
      EXPECT_GE(heights[i], dem->info.minM);
      EXPECT_LE(heights[i], dem->info.maxM);
    } else {
      ASSERT_EQ(heights[i], dem->field.heights[i]) << i;
    }
  }
  EXPECT_EQ(voids, 9033);
}

}  // namespace
}  // namespace polder::terrain
