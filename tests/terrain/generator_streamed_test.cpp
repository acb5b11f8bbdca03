// The streamed generator: rows independent of how they are asked for, the base's shape kept,
// detail where the base is steep and not where erosion smoothed it.
#include <polder/terrain/generator_streamed.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include <polder/thread_pool.hpp>

namespace polder::terrain {
namespace {

GeneratorOptions options(int size, double spacingM) {
  GeneratorOptions o;
  o.size = size;
  o.spacingM = spacingM;
  o.seed = 11;
  return o;
}

std::vector<float> rows(const StreamedTerrain& terrain, int y0, int count, core::ThreadPool* pool = nullptr) {
  std::vector<float> out(std::size_t(count) * std::size_t(terrain.size()));
  const Status made = terrain.generateRows(y0, count, out, pool);
  EXPECT_TRUE(made.ok()) << made.error().message;
  return out;
}

// Mean slope (rise over run) of a raster of `size` columns.
double meanSlope(const std::vector<float>& heights, int width, double spacing) {
  const int height = int(heights.size() / std::size_t(width));
  double sum = 0.0;
  int n = 0;
  for (int y = 0; y + 1 < height; ++y)
    for (int x = 0; x + 1 < width; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(width) + std::size_t(x);
      const double gx = (heights[i + 1] - heights[i]) / spacing;
      const double gy = (heights[i + std::size_t(width)] - heights[i]) / spacing;
      sum += std::sqrt(gx * gx + gy * gy);
      ++n;
    }
  return sum / n;
}

TEST(StreamedTerrain, RowsAreTheSameWhateverTheBandsAndThreads) {
  auto terrain = StreamedTerrain::create(options(1025, 10.0), 129);
  ASSERT_TRUE(terrain.ok()) << terrain.error().message;
  EXPECT_EQ(terrain->base().width, 129);
  const auto whole = rows(*terrain, 0, 1025);
  core::ThreadPool pool(2);
  const auto pooled = rows(*terrain, 0, 1025, &pool);
  EXPECT_EQ(whole, pooled);
  for (const int y0 : {0, 1, 300, 1018}) {
    const auto band = rows(*terrain, y0, 7);
    ASSERT_TRUE(std::equal(band.begin(), band.end(), whole.begin() + std::ptrdiff_t(y0) * 1025)) << y0;
  }
  auto again = StreamedTerrain::create(options(1025, 10.0), 129);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(rows(*again, 500, 3), rows(*terrain, 500, 3)) << "the same options, the same heights";
  GeneratorOptions other = options(1025, 10.0);
  other.seed = 12;
  auto different = StreamedTerrain::create(other, 129);
  ASSERT_TRUE(different.ok());
  EXPECT_NE(rows(*different, 500, 3), rows(*terrain, 500, 3));
}

TEST(StreamedTerrain, FollowsTheErodedBaseAndAddsRoughnessWhereItIsSteep) {
  const int size = 1025, baseSize = 129;
  auto terrain = StreamedTerrain::create(options(size, 10.0), baseSize);
  ASSERT_TRUE(terrain.ok()) << terrain.error().message;
  const auto full = rows(*terrain, 0, size);
  const Heightfield& base = terrain->base();
  const int stride = (size - 1) / (baseSize - 1);

  // At the base's samples the full raster stays near the base: the detail is small against
  // the relief, and the heights' range is the base's.
  double baseLow = 1e30, baseHigh = -1e30, deviation = 0.0;
  for (int j = 0; j < baseSize; ++j)
    for (int i = 0; i < baseSize; ++i) {
      const double b = base.at(i, j);
      baseLow = std::min(baseLow, b);
      baseHigh = std::max(baseHigh, b);
      deviation += std::abs(full[std::size_t(j * stride) * size + std::size_t(i * stride)] - b);
    }
  deviation /= double(baseSize) * baseSize;
  const double relief = baseHigh - baseLow;
  EXPECT_GT(relief, 200.0);
  EXPECT_LT(deviation, 0.05 * relief);
  const auto [low, high] = std::minmax_element(full.begin(), full.end());
  EXPECT_NEAR(*high - *low, relief, 0.25 * relief);

  // Detail: the full raster is rougher than a smooth interpolation of the base would be
  // (its mean slope rises), but not wildly.
  std::vector<float> baseHeights(base.heights.begin(), base.heights.end());
  const double baseSlope = meanSlope(baseHeights, baseSize, base.spacingX);
  const double fullSlope = meanSlope(full, size, 10.0);
  EXPECT_GT(fullSlope, 1.5 * baseSlope);
  EXPECT_LT(fullSlope, 4.0 * baseSlope);

  // Flat ground (valley floors, filled lakes) stays smooth: where the base is near flat over a
  // base cell, the full raster is too.
  int flatCells = 0;
  double flatRoughness = 0.0, steepRoughness = 0.0;
  int steepCells = 0;
  for (int j = 1; j + 2 < baseSize; ++j)
    for (int i = 1; i + 2 < baseSize; ++i) {
      double lo = 1e30, hi = -1e30;
      for (int dj = -1; dj <= 2; ++dj)
        for (int di = -1; di <= 2; ++di) {
          lo = std::min(lo, double(base.at(i + di, j + dj)));
          hi = std::max(hi, double(base.at(i + di, j + dj)));
        }
      // Second differences inside the cell measure the detail's roughness.
      double rough = 0.0;
      for (int y = j * stride + 1; y < (j + 1) * stride; ++y)
        for (int x = i * stride + 1; x < (i + 1) * stride; ++x) {
          const std::size_t at = std::size_t(y) * size + std::size_t(x);
          rough += std::abs(full[at - 1] - 2.0 * full[at] + full[at + 1]);
        }
      if (hi - lo < 0.5) {
        ++flatCells;
        flatRoughness += rough;
      } else if (hi - lo > 0.2 * stride * 10.0 * 3.0) {
        ++steepCells;
        steepRoughness += rough;
      }
    }
  ASSERT_GT(flatCells, 0);
  ASSERT_GT(steepCells, 0);
  EXPECT_LT(flatRoughness / flatCells, 0.1 * steepRoughness / steepCells);
}

TEST(StreamedTerrain, RefusesBadOptionsAndRows) {
  EXPECT_FALSE(StreamedTerrain::create(options(kMaxStreamedGeneratorSize + 1, 10.0)).ok());
  EXPECT_FALSE(StreamedTerrain::create(options(1025, -1.0)).ok());
  EXPECT_FALSE(StreamedTerrain::create(options(1025, 10.0), 3).ok());
  auto terrain = StreamedTerrain::create(options(65, 10.0), 33);
  ASSERT_TRUE(terrain.ok()) << terrain.error().message;
  std::vector<float> out(65 * 2);
  EXPECT_FALSE(terrain->generateRows(64, 2, out).ok());
  EXPECT_FALSE(terrain->generateRows(-1, 2, out).ok());
  EXPECT_FALSE(terrain->generateRows(0, 3, out).ok()) << "a buffer of the wrong size";
  EXPECT_TRUE(terrain->generateRows(63, 2, out).ok());
  auto capped = StreamedTerrain::create(options(65, 10.0), 4097);
  ASSERT_TRUE(capped.ok());
  EXPECT_EQ(capped->base().width, 65) << "the base is never larger than the raster";
}

}  // namespace
}  // namespace polder::terrain
