#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <polder/terrain/geotiff.hpp>

#include "wgs84_reference.hpp"

namespace polder::terrain {
namespace {

using test::metresPerDegreeLatitude;
using test::metresPerDegreeLongitude;

std::vector<std::uint16_t> keys(std::initializer_list<std::pair<std::uint16_t, std::uint16_t>> entries) {
  std::vector<std::uint16_t> directory = {1, 1, 0, std::uint16_t(entries.size())};
  for (auto [id, value] : entries) directory.insert(directory.end(), {id, 0, 1, value});
  return directory;
}

TEST(GeoSpacing, DegreeLengthsMatchTheReferenceSeries) {
  for (double latitude : {0.0, 23.5, 46.5, -60.0, 80.0}) {
    const GroundSpacing perDegree = metresPerDegree(latitude);
    EXPECT_NEAR(perDegree.y, metresPerDegreeLatitude(latitude), 1.0) << latitude;
    EXPECT_NEAR(perDegree.x, metresPerDegreeLongitude(latitude), 1.0) << latitude;
  }
  EXPECT_NEAR(webMercatorLatitude(0.0), 0.0, 1e-12);
  EXPECT_NEAR(webMercatorLatitude(20037508.342789244), 85.0511287798, 1e-6);
  EXPECT_NEAR(webMercatorLatitude(-20037508.342789244), -85.0511287798, 1e-6);
}

TEST(GeoTiffSpacing, GeographicDegreesAtTheCentreLatitude) {
  // The Mt Rainier SRTM tile: 3" pixels, PixelIsArea, north-west corner at 47.0004 N.
  GeoTiffTags tags;
  tags.pixelScale = {1.0 / 1200.0, 1.0 / 1200.0, 0.0};
  tags.tiepoint = {0, 0, 0, -122.00041666666667, 47.000416666666666, 0};
  tags.geoKeys = keys({{1024, 2}, {1025, 1}, {2048, 4326}, {2054, 9102}});
  const auto spacing = geoTiffSpacing(tags, 1201, 1201);
  ASSERT_TRUE(spacing.ok());
  ASSERT_TRUE(spacing->has_value());
  EXPECT_NEAR((*spacing)->y, metresPerDegreeLatitude(46.5) / 1200.0, 0.01);   // ~92.6
  EXPECT_NEAR((*spacing)->x, metresPerDegreeLongitude(46.5) / 1200.0, 0.01);  // ~64.0
}

TEST(GeoTiffSpacing, PixelIsPointShiftsTheCentreByHalfAPixel) {
  // ETOPO5-like: 5' pixels, points from 90 N to 90 S, centre on the equator.
  GeoTiffTags tags;
  tags.pixelScale = {1.0 / 12.0, 1.0 / 12.0, 0.0};
  tags.tiepoint = {0, 0, 0, 0.0, 90.0, 0};
  tags.geoKeys = keys({{1024, 2}, {1025, 2}});
  const auto spacing = geoTiffSpacing(tags, 4320, 2161);
  ASSERT_TRUE(spacing.ok() && spacing->has_value());
  EXPECT_NEAR((*spacing)->x, metresPerDegreeLongitude(0.0) / 12.0, 0.05);
  EXPECT_NEAR((*spacing)->y, metresPerDegreeLatitude(0.0) / 12.0, 0.05);
}

TEST(GeoTiffSpacing, WebMercatorShrinksByCosLatitude) {
  GeoTiffTags tags;
  tags.pixelScale = {9783.93962050256, 9783.93962050256, 0.0};
  tags.tiepoint = {0, 0, 0, -20037508.342789244, 20037508.342789244, 0};
  tags.geoKeys = keys({{1024, 1}, {1025, 1}, {3072, 3857}, {3076, 9001}});
  auto spacing = geoTiffSpacing(tags, 4096, 4096);  // the whole world: centre on the equator
  ASSERT_TRUE(spacing.ok() && spacing->has_value());
  EXPECT_NEAR((*spacing)->x, 9783.94, 0.01);
  EXPECT_NEAR((*spacing)->y, 9783.94, 0.01);

  // Only the northern half: centred at 66.51 N (mercator y = 10018754).
  spacing = geoTiffSpacing(tags, 4096, 2048);
  ASSERT_TRUE(spacing.ok() && spacing->has_value());
  const double latitude = webMercatorLatitude(20037508.342789244 / 2);
  EXPECT_NEAR(latitude, 66.513, 0.001);
  EXPECT_NEAR((*spacing)->x, 9783.93962050256 * std::cos(latitude * M_PI / 180.0), 0.01);
}

TEST(GeoTiffSpacing, ProjectedUnitsAndBareScales) {
  GeoTiffTags tags;
  tags.pixelScale = {30.0, 25.0, 0.0};
  tags.geoKeys = keys({{1024, 1}, {3072, 32610}});  // UTM 10N, metres by default
  auto spacing = geoTiffSpacing(tags, 10, 10);
  ASSERT_TRUE(spacing.ok() && spacing->has_value());
  EXPECT_DOUBLE_EQ((*spacing)->x, 30.0);
  EXPECT_DOUBLE_EQ((*spacing)->y, 25.0);

  tags.geoKeys = keys({{1024, 1}, {3076, 9002}});  // international feet
  spacing = geoTiffSpacing(tags, 10, 10);
  ASSERT_TRUE(spacing.ok() && spacing->has_value());
  EXPECT_DOUBLE_EQ((*spacing)->x, 30.0 * 0.3048);

  tags.geoKeys.clear();  // a pixel size and nothing else: metres
  spacing = geoTiffSpacing(tags, 10, 10);
  ASSERT_TRUE(spacing.ok() && spacing->has_value());
  EXPECT_DOUBLE_EQ((*spacing)->y, 25.0);

  tags.pixelScale.clear();  // nothing at all
  spacing = geoTiffSpacing(tags, 10, 10);
  ASSERT_TRUE(spacing.ok());
  EXPECT_FALSE(spacing->has_value());
}

TEST(GeoTiffSpacing, ModelTransformationInsteadOfScale) {
  GeoTiffTags tags;
  tags.transformation = {20, 0, 0, 500000, 0, -10, 0, 4000000, 0, 0, 0, 0, 0, 0, 0, 1};
  const auto spacing = geoTiffSpacing(tags, 100, 100);
  ASSERT_TRUE(spacing.ok() && spacing->has_value());
  EXPECT_DOUBLE_EQ((*spacing)->x, 20.0);
  EXPECT_DOUBLE_EQ((*spacing)->y, 10.0);
}

// A pixel size that is given but unusable is bad data, not "no georeferencing": 1 m in its
// place would silently misscale the terrain.
TEST(GeoTiffSpacing, GivenButUnusablePixelSizesAreInvalidData) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const std::vector<double>& scale : std::vector<std::vector<double>>{
           {0.0, 0.0, 0.0}, {30.0, 0.0, 0.0}, {nan, 30.0, 0.0}, {30.0, inf, 0.0}, {nan, nan, nan}}) {
    GeoTiffTags tags;
    tags.pixelScale = scale;
    const auto spacing = geoTiffSpacing(tags, 10, 10);
    ASSERT_FALSE(spacing.ok()) << scale[0] << " x " << scale[1];
    EXPECT_EQ(spacing.error().kind, ErrorKind::InvalidData);
    EXPECT_NE(spacing.error().message.find("pixel size"), std::string::npos);
  }
  GeoTiffTags flat;
  flat.transformation = {0, 0, 0, 500000, 0, 0, 0, 4000000, 0, 0, 0, 0, 0, 0, 0, 1};  // all pixels at one point
  EXPECT_FALSE(geoTiffSpacing(flat, 10, 10).ok());
}

TEST(GeoTiffSpacing, UnknownUnitsAndModelsAreUnsupported) {
  GeoTiffTags tags;
  tags.pixelScale = {1.0, 1.0, 0.0};
  tags.geoKeys = keys({{1024, 1}, {3076, 9099}});
  auto spacing = geoTiffSpacing(tags, 10, 10);
  ASSERT_FALSE(spacing.ok());
  EXPECT_EQ(spacing.error().kind, ErrorKind::Unsupported);
  EXPECT_NE(spacing.error().message.find("9099"), std::string::npos);

  tags.geoKeys = keys({{1024, 3}});
  spacing = geoTiffSpacing(tags, 10, 10);
  ASSERT_FALSE(spacing.ok());
  EXPECT_EQ(spacing.error().kind, ErrorKind::Unsupported);
}

TEST(GeoTiffSpacing, GeoKeyLookupIgnoresTruncatedDirectories) {
  EXPECT_EQ(geoKeyValue(keys({{1024, 2}, {3072, 3857}}), 3072), 3857);
  EXPECT_EQ(geoKeyValue(keys({{1024, 2}}), 3072), std::nullopt);
  std::vector<std::uint16_t> truncated = {1, 1, 0, 5, 1024, 0, 1};  // says 5 keys, holds none whole
  EXPECT_EQ(geoKeyValue(truncated, 1024), std::nullopt);
  EXPECT_EQ(geoKeyValue({}, 1024), std::nullopt);
}

TEST(GdalNodata, ParsesNumbersAndNaN) {
  EXPECT_EQ(*parseGdalNodata("-32768"), -32768.0);
  EXPECT_EQ(*parseGdalNodata(" -9999 "), -9999.0);
  EXPECT_EQ(*parseGdalNodata("-3.4028234663852886e+38"), -3.4028234663852886e+38);
  EXPECT_TRUE(std::isnan(*parseGdalNodata("nan")));
  const auto bad = parseGdalNodata("none");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().kind, ErrorKind::InvalidData);
  EXPECT_NE(bad.error().message.find("'none'"), std::string::npos);
}

}  // namespace
}  // namespace polder::terrain
