// GeoTIFF georeferencing and no-data through readDem, with tags written by libtiff.
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

using test::geoKeyDirectory;
using test::GeoTags;
using test::ScratchDir;

std::vector<std::int16_t> hills(int width, int height) {
  std::vector<std::int16_t> values;
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c) values.push_back(std::int16_t(500 + 7 * r - 3 * c));
  return values;
}

TEST(ReadGeoTiff, GeographicDegreesBecomeMetresAtTheCentreLatitude) {
  // 30" pixels, PixelIsArea, north-west corner at 61 N: the centre is at 60 N.
  ScratchDir dir;
  GeoTags tags;
  tags.pixelScale = {1.0 / 120.0, 1.0 / 120.0, 0.0};
  tags.tiepoint = {0, 0, 0, 10.0, 61.0, 0};
  tags.geoKeys = geoKeyDirectory({{1024, 2}, {1025, 1}, {2048, 4326}, {2054, 9102}});
  test::writeGeoTiff(dir.file("degrees.tif"), 240, 240, hills(240, 240), tags);
  const auto dem = readDem(dir.file("degrees.tif"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->info.format, "geotiff");
  EXPECT_FALSE(dem->info.spacingAssumed);
  EXPECT_NEAR(dem->field.spacingY, test::metresPerDegreeLatitude(60.0) / 120.0, 0.01);   // ~927 m
  EXPECT_NEAR(dem->field.spacingX, test::metresPerDegreeLongitude(60.0) / 120.0, 0.01);  // ~465 m
  EXPECT_EQ(dem->field.at(0, 239), 500.0f);                                              // north-west
}

TEST(ReadGeoTiff, ProjectedMetresAndFeet) {
  ScratchDir dir;
  GeoTags tags;
  tags.pixelScale = {25.0, 30.0, 0.0};
  tags.tiepoint = {0, 0, 0, 500000.0, 5200000.0, 0};
  tags.geoKeys = geoKeyDirectory({{1024, 1}, {1025, 1}, {3072, 32610}});
  test::writeGeoTiff(dir.file("utm.tif"), 40, 30, hills(40, 30), tags, true);
  auto dem = readDem(dir.file("utm.tif"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_DOUBLE_EQ(dem->field.spacingX, 25.0);
  EXPECT_DOUBLE_EQ(dem->field.spacingY, 30.0);
  EXPECT_EQ(dem->field.at(39, 0), float(500 + 7 * 29 - 3 * 39));  // tiled + deflate read right

  tags.geoKeys = geoKeyDirectory({{1024, 1}, {3076, 9002}});
  test::writeGeoTiff(dir.file("feet.tif"), 40, 30, hills(40, 30), tags);
  dem = readDem(dir.file("feet.tif"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_DOUBLE_EQ(dem->field.spacingX, 25.0 * 0.3048);

  DemOptions options;
  options.spacingM = 2.0;  // the option beats the file
  dem = readDem(dir.file("feet.tif"), options);
  ASSERT_TRUE(dem.ok());
  EXPECT_EQ(dem->field.spacingX, 2.0);
  EXPECT_EQ(dem->field.spacingY, 2.0);
}

TEST(ReadGeoTiff, WebMercatorGroundSpacing) {
  // A z10-like tile near 60 N: 256 px of 152.87 m mercator units.
  ScratchDir dir;
  const double units = 152.87405657041106;
  const double northM = 8414168.0;  // mercator y of the tile's top edge
  GeoTags tags;
  tags.pixelScale = {units, units, 0.0};
  tags.tiepoint = {0, 0, 0, 1000000.0, northM, 0};
  tags.geoKeys = geoKeyDirectory({{1024, 1}, {1025, 1}, {3072, 3857}, {3076, 9001}});
  test::writeGeoTiff(dir.file("mercator.tif"), 256, 256, hills(256, 256), tags, true);
  const auto dem = readDem(dir.file("mercator.tif"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  const double centreY = northM - 128.0 * units;
  const double latitude = 2.0 * std::atan(std::exp(centreY / 6378137.0)) - M_PI / 2.0;
  EXPECT_NEAR(latitude * 180.0 / M_PI, 60.0, 0.2);
  EXPECT_NEAR(dem->field.spacingX, units * std::cos(latitude), 1e-6);
  EXPECT_NEAR(dem->field.spacingY, units * std::cos(latitude), 1e-6);
}

TEST(ReadGeoTiff, GdalNodataValueMarksVoids) {
  ScratchDir dir;
  std::vector<float> values(30 * 20, 0.0f);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = 100.0f + float(i % 30);
  values[47] = -9999.0f;
  values[48] = -9999.0f;
  values[400] = -9999.0f;
  GeoTags tags;
  tags.pixelScale = {10.0, 10.0, 0.0};
  tags.nodata = "-9999";
  test::writeGeoTiff(dir.file("nodata.tif"), 30, 20, values, tags, true);
  auto dem = readDem(dir.file("nodata.tif"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->info.voids, 3);
  EXPECT_GE(dem->info.minM, 100.0);
  EXPECT_EQ(dem->info.encoding, "float32");

  DemOptions options;
  options.nodataEnabled = false;
  dem = readDem(dir.file("nodata.tif"), options);
  ASSERT_TRUE(dem.ok());
  EXPECT_EQ(dem->info.voids, 0);
  EXPECT_EQ(dem->info.minM, -9999.0);
}

TEST(ReadGeoTiff, NanNodataAndInt16Nodata) {
  ScratchDir dir;
  std::vector<float> values(16 * 16, 5.0f);
  values[3] = std::numeric_limits<float>::quiet_NaN();
  GeoTags tags;
  tags.nodata = "nan";
  test::writeGeoTiff(dir.file("nan.tif"), 16, 16, values, tags);
  auto dem = readDem(dir.file("nan.tif"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->info.voids, 1);
  EXPECT_EQ(dem->field.at(3, 15), 5.0f);
  EXPECT_TRUE(dem->info.spacingAssumed);  // no pixel scale

  auto shorts = hills(16, 16);
  shorts[0] = -32768;  // int16 rule
  shorts[1] = 0;       // GDAL_NODATA 0
  tags.nodata = "0";
  test::writeGeoTiff(dir.file("int16.tif"), 16, 16, shorts, tags);
  dem = readDem(dir.file("int16.tif"), {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->info.voids, 2);
}

}  // namespace
}  // namespace polder::terrain
