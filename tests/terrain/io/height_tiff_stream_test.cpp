// The band writer's files read back exactly, tiled, through both readers; nothing half-written
// is ever left under the destination's name.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include <tiffio.h>

#include <polder/terrain/dem_reader.hpp>
#include <polder/terrain/dem_rows.hpp>
#include <polder/terrain/height_tiff_stream.hpp>

#include "test_support.hpp"

namespace polder::terrain {
namespace {

using test::ScratchDir;

// Height of column x, row r counted from the north.
float heightAt(int x, int r) { return float(100.0 + 700.0 * std::sin(x * 0.031) * std::cos(r * 0.017) + 0.25 * r); }

std::vector<float> northBand(int width, int firstRow, int count) {
  std::vector<float> band(std::size_t(width) * std::size_t(count));
  for (int r = 0; r < count; ++r)
    for (int x = 0; x < width; ++x)
      band[std::size_t(r) * std::size_t(width) + std::size_t(x)] = heightAt(x, firstRow + r);
  return band;
}

Status writeAll(HeightTiffStream& writer) {
  while (writer.rowsWritten() < writer.height()) {
    const int count = std::min(HeightTiffStream::kTileSize, writer.height() - writer.rowsWritten());
    if (Status written = writer.writeRows(count, northBand(writer.width(), writer.rowsWritten(), count)); !written)
      return written;
  }
  return writer.finish();
}

std::size_t filesIn(const std::filesystem::path& folder) {
  return std::size_t(std::distance(std::filesystem::directory_iterator(folder), {}));
}

TEST(HeightTiffStream, WritesATiledGeoTiffThatBothReadersReadExactly) {
  ScratchDir dir;
  const auto path = dir.file("big.tif");
  const int width = 600, height = 530;  // partial tiles on the east and south edges
  auto writer = HeightTiffStream::create(path, width, height, 12.5, 7.0);
  ASSERT_TRUE(writer.ok()) << writer.error().message;
  EXPECT_FALSE(std::filesystem::exists(path)) << "not under its name before finish()";
  ASSERT_TRUE(writeAll(**writer).ok());
  EXPECT_EQ(filesIn(dir.path()), 1u) << "no temporary file left";

  const auto dem = readDem(path, {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->field.width, width);
  EXPECT_EQ(dem->field.height, height);
  EXPECT_EQ(dem->field.spacingX, 12.5);
  EXPECT_EQ(dem->field.spacingY, 7.0);
  EXPECT_FALSE(dem->info.spacingAssumed);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) ASSERT_EQ(dem->field.at(x, y), heightAt(x, height - 1 - y)) << x << "," << y;

  auto rows = openDemRows(path, {});
  ASSERT_TRUE(rows.ok()) << rows.error().message;
  EXPECT_TRUE((*rows)->streamed());
  std::vector<float> band(std::size_t(3) * width);
  ASSERT_TRUE((*rows)->readRows(250, 3, band).ok());
  for (int x = 0; x < width; ++x) EXPECT_EQ(band[std::size_t(x)], heightAt(x, height - 1 - 250));

  TIFF* tiff = TIFFOpen(path.c_str(), "r");
  ASSERT_NE(tiff, nullptr);
  EXPECT_TRUE(TIFFIsTiled(tiff));
  std::uint32_t tileWidth = 0;
  TIFFGetField(tiff, TIFFTAG_TILEWIDTH, &tileWidth);
  EXPECT_EQ(tileWidth, std::uint32_t(HeightTiffStream::kTileSize));
  TIFFClose(tiff);
}

TEST(HeightTiffStream, RefusesWrongBandsAndNonFiniteHeightsAndLeavesNoFile) {
  ScratchDir dir;
  const auto path = dir.file("refused.tif");
  {
    auto writer = HeightTiffStream::create(path, 300, 300, 1.0, 1.0);
    ASSERT_TRUE(writer.ok()) << writer.error().message;
    const auto wrong = (*writer)->writeRows(10, northBand(300, 0, 10));
    ASSERT_FALSE(wrong.ok());
    EXPECT_EQ(int(wrong.error().kind), int(ErrorKind::InvalidArgument));
    EXPECT_NE(wrong.error().message.find("refused.tif"), std::string::npos) << wrong.error().message;
    auto band = northBand(300, 0, 256);
    band[1000] = std::numeric_limits<float>::quiet_NaN();
    const auto nan = (*writer)->writeRows(256, band);
    ASSERT_FALSE(nan.ok());
    EXPECT_NE(nan.error().message.find("column 100, row 3"), std::string::npos) << nan.error().message;
    EXPECT_FALSE((*writer)->writeRows(256, northBand(300, 0, 256)).ok()) << "nothing after a failure";
    EXPECT_FALSE((*writer)->finish().ok());
  }
  EXPECT_EQ(filesIn(dir.path()), 0u);
  {
    auto writer = HeightTiffStream::create(path, 300, 300, 1.0, 1.0);
    ASSERT_TRUE(writer.ok());
    ASSERT_TRUE((*writer)->writeRows(256, northBand(300, 0, 256)).ok());
    const auto early = (*writer)->finish();
    ASSERT_FALSE(early.ok());
    EXPECT_NE(early.error().message.find("256 of 300 rows"), std::string::npos) << early.error().message;
  }
  EXPECT_EQ(filesIn(dir.path()), 0u) << "abandoned half-way: nothing left";

  EXPECT_FALSE(HeightTiffStream::create(path, 0, 10, 1.0, 1.0).ok());
  EXPECT_FALSE(HeightTiffStream::create(path, 10, 10, 0.0, 1.0).ok());
  EXPECT_FALSE(HeightTiffStream::create(path, 10, 10, 1.0, std::nan("")).ok());
  const auto noFolder = HeightTiffStream::create(dir.file("missing/x.tif"), 10, 10, 1.0, 1.0);
  ASSERT_FALSE(noFolder.ok());
  EXPECT_EQ(int(noFolder.error().kind), int(ErrorKind::Io));
  // Larger than any disk: refused before anything is written.
  const auto huge = HeightTiffStream::create(path, 2'000'000'000, 2'000'000'000, 1.0, 1.0);
  ASSERT_FALSE(huge.ok());
  EXPECT_NE(huge.error().message.find("free"), std::string::npos) << huge.error().message;
  EXPECT_EQ(filesIn(dir.path()), 0u);
}

}  // namespace
}  // namespace polder::terrain
