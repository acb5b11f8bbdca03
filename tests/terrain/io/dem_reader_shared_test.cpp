// The real DEMs of the shared data folder (dems/); skipped when absent.
#include <gtest/gtest.h>

#include <polder/terrain/dem_reader.hpp>

#include "dem_test_files.hpp"
#include "test_support.hpp"

namespace polder::terrain {
namespace {

TEST(SharedDems, MtRainierSrtmGeoTiff) {
  POLDER_REQUIRE_SHARED_FILE(path, "dems/mt_rainier_90m_srtm3.tif");
  const auto dem = readDem(path, {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->field.width, 1201);
  EXPECT_EQ(dem->field.height, 1201);
  EXPECT_EQ(dem->info.format, "geotiff");
  EXPECT_EQ(dem->info.encoding, "int16");
  EXPECT_EQ(dem->info.voids, 9033);
  EXPECT_NEAR(dem->info.minM, 263.0, 0.5);  // voids are filled within the valid range
  EXPECT_EQ(dem->info.maxM, 4371.0);
  EXPECT_FALSE(dem->info.spacingAssumed);
  // 3 arc-seconds at 46.5 N.
  EXPECT_NEAR(dem->field.spacingY, test::metresPerDegreeLatitude(46.5) / 1200.0, 0.02);   // ~92.6 m
  EXPECT_NEAR(dem->field.spacingX, test::metresPerDegreeLongitude(46.5) / 1200.0, 0.02);  // ~64.0 m
  EXPECT_NEAR(dem->field.spacingY, 92.6, 0.1);
  EXPECT_NEAR(dem->field.spacingX, 64.0, 0.1);
  // Mt Rainier's summit (46.853 N, 121.760 W) is the maximum: in the north half, east of centre.
  int bestX = 0, bestY = 0;
  for (int y = 0; y < dem->field.height; ++y)
    for (int x = 0; x < dem->field.width; ++x)
      if (dem->field.at(x, y) > dem->field.at(bestX, bestY)) bestX = x, bestY = y;
  EXPECT_NEAR(-122.0 + bestX / 1200.0, -121.760, 0.01);
  EXPECT_NEAR(46.0 + bestY / 1200.0, 46.853, 0.01);
}

TEST(SharedDems, FujiTerrainRgb) {
  POLDER_REQUIRE_SHARED_FILE(path, "dems/fuji_terrainrgb_martini.png");
  const auto dem = readDem(path, {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->field.width, 512);
  EXPECT_EQ(dem->field.height, 512);
  EXPECT_EQ(dem->info.encoding, "terrain-rgb");
  EXPECT_NEAR(dem->info.minM, 13.7, 0.05);
  EXPECT_NEAR(dem->info.maxM, 3751.0, 0.05);
  EXPECT_EQ(dem->info.voids, 0);
  EXPECT_TRUE(dem->info.spacingAssumed);
}

TEST(SharedDems, BayAreaTerrainRgb) {
  POLDER_REQUIRE_SHARED_FILE(path, "dems/bayarea_z14_2625_6369_terrainrgb_delatin.png");
  const auto dem = readDem(path, {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->field.width, 512);
  EXPECT_EQ(dem->info.encoding, "terrain-rgb");
  EXPECT_NEAR(dem->info.minM, 19.0, 0.05);
  EXPECT_NEAR(dem->info.maxM, 251.8, 0.05);
}

TEST(SharedDems, HimalayaTerrarium) {
  POLDER_REQUIRE_SHARED_FILE(path, "dems/terrarium_z5_x23_y13.png");
  const auto dem = readDem(path, {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->field.width, 256);
  EXPECT_EQ(dem->info.encoding, "terrarium");
  EXPECT_NEAR(dem->info.minM, -1.0, 0.5);
  EXPECT_NEAR(dem->info.maxM, 7188.0, 0.5);
  // The Himalaya are in the tile's north: the north half is far higher than the south.
  double north = 0.0, south = 0.0;
  for (int x = 0; x < 256; ++x) north += dem->field.at(x, 240), south += dem->field.at(x, 15);
  EXPECT_GT(north, south);
}

TEST(SharedDems, PugetSoundWithSpacingAndScale) {
  POLDER_REQUIRE_SHARED_FILE(path, "dems/puget_sound_ps_height_1k.png");
  DemOptions options;
  options.spacingM = 160.0;
  options.zScale = 0.1;
  const auto dem = readDem(path, options);
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->field.width, 1025);
  EXPECT_EQ(dem->field.height, 1025);
  EXPECT_EQ(dem->field.spacingX, 160.0);
  EXPECT_EQ(dem->info.encoding, "uint16");
  EXPECT_NEAR(dem->info.maxM, 4379.8, 1e-3);
  EXPECT_EQ(dem->info.minM, 0.0);
  EXPECT_EQ(dem->info.voids, 0);

  const auto plain = readDem(path, {});
  ASSERT_TRUE(plain.ok());
  EXPECT_TRUE(plain->info.spacingAssumed);
  EXPECT_EQ(plain->info.maxM, 43798.0);
}

TEST(SharedDems, Etopo5Global) {
  POLDER_REQUIRE_SHARED_FILE(path, "dems/etopo5_global_4320x2161_int16.tif");
  const auto dem = readDem(path, {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->field.width, 4320);
  EXPECT_EQ(dem->field.height, 2161);
  EXPECT_EQ(dem->info.format, "geotiff");
  EXPECT_EQ(dem->info.voids, 0);
  EXPECT_EQ(dem->info.minM, -10376.0);
  EXPECT_EQ(dem->info.maxM, 7833.0);
  EXPECT_EQ(dem->field.at(0, 2160), -4290.0f);  // the file's first row: the north pole
  EXPECT_EQ(dem->field.at(0, 0), 2810.0f);      // its last: the south pole
  // 5 arc-minutes at the equator (the raster's centre latitude): about 9.3 km.
  EXPECT_NEAR(dem->field.spacingX, test::metresPerDegreeLongitude(0.0) / 12.0, 1.0);
  EXPECT_NEAR(dem->field.spacingY, test::metresPerDegreeLatitude(0.0) / 12.0, 1.0);
  EXPECT_NEAR(dem->field.spacingX, 9277.0, 5.0);
}

TEST(SharedDems, TerrariumWorldWebMercator) {
  POLDER_REQUIRE_SHARED_FILE(path, "dems/terrarium_world_z4_4096x4096_int16.tif");
  const auto dem = readDem(path, {});
  ASSERT_TRUE(dem.ok()) << dem.error().message;
  EXPECT_EQ(dem->field.width, 4096);
  EXPECT_EQ(dem->field.height, 4096);
  EXPECT_EQ(dem->info.format, "geotiff");
  EXPECT_NEAR(dem->field.spacingX, 9783.94, 0.01);  // the centre is on the equator
  EXPECT_NEAR(dem->field.spacingY, 9783.94, 0.01);
  EXPECT_EQ(dem->info.minM, -10467.0);
  EXPECT_EQ(dem->info.maxM, 11500.0);  // the known spike at rows 832-833, column 1151
  EXPECT_EQ(dem->field.at(1151, 4095 - 832), 11500.0f);
}

}  // namespace
}  // namespace polder::terrain
