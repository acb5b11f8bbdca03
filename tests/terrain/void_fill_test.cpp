#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include <polder/terrain/void_fill.hpp>

namespace polder::terrain {
namespace {

constexpr float kVoid = std::numeric_limits<float>::quiet_NaN();

Heightfield plane(int width, int height, double a, double b, double c) {
  Heightfield field(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) field.at(x, y) = float(a * x + b * y + c);
  return field;
}

TEST(FillVoids, NoVoidsChangesNothing) {
  Heightfield field = plane(9, 7, 1.0, 2.0, 3.0);
  const Heightfield before = field;
  EXPECT_EQ(fillVoids(field), 0);
  EXPECT_EQ(field.heights, before.heights);
}

TEST(FillVoids, AllVoidsIsLeftAlone) {
  Heightfield field(4, 4);
  for (float& h : field.heights) h = kVoid;
  EXPECT_EQ(countVoids(field), 16);
  EXPECT_EQ(fillVoids(field), 16);
  EXPECT_TRUE(std::isnan(field.at(2, 2)));
}

TEST(FillVoids, SingleVoidInAPlaneIsExact) {
  Heightfield field = plane(16, 16, 2.0, -3.0, 100.0);
  field.at(7, 9) = kVoid;
  EXPECT_EQ(fillVoids(field), 1);
  EXPECT_NEAR(field.at(7, 9), 2.0 * 7 - 3.0 * 9 + 100.0, 1e-3);
}

TEST(FillVoids, ConstantFieldStaysConstant) {
  Heightfield field(50, 40);
  for (float& h : field.heights) h = 123.5f;
  for (int y = 5; y < 30; ++y)
    for (int x = 10; x < 45; ++x) field.at(x, y) = kVoid;
  EXPECT_EQ(fillVoids(field), 25 * 35);
  for (float h : field.heights) EXPECT_FLOAT_EQ(h, 123.5f);
}

TEST(FillVoids, KeepsValidSamplesAndStaysWithinTheirRange) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> height(-50.0f, 900.0f);
  Heightfield field(97, 61);
  for (float& h : field.heights) h = height(random);
  Heightfield original = field;
  std::bernoulli_distribution isVoid(0.3);
  for (std::size_t i = 0; i < field.heights.size(); ++i)
    if (isVoid(random)) field.heights[i] = kVoid;
  const std::int64_t voids = countVoids(field);
  float low = 1e9f, high = -1e9f;
  for (float h : field.heights)
    if (!std::isnan(h)) low = std::min(low, h), high = std::max(high, h);

  Heightfield filled = field;
  EXPECT_EQ(fillVoids(filled), voids);
  for (std::size_t i = 0; i < field.heights.size(); ++i) {
    ASSERT_FALSE(std::isnan(filled.heights[i])) << i;
    if (!std::isnan(field.heights[i])) {
      EXPECT_EQ(filled.heights[i], field.heights[i]);
    }
    EXPECT_GE(filled.heights[i], low - 1e-3f);
    EXPECT_LE(filled.heights[i], high + 1e-3f);
  }
}

TEST(FillVoids, LargeHoleInASlopeFollowsTheSlope) {
  // A 60 x 60 hole in a tilted plane: the fill should be a smooth surface close to it,
  // not a flat patch at the mean.
  Heightfield field = plane(256, 256, 1.0, 0.5, 0.0);
  const Heightfield truth = field;
  for (int y = 100; y < 160; ++y)
    for (int x = 90; x < 150; ++x) field.at(x, y) = kVoid;
  EXPECT_EQ(fillVoids(field), 3600);
  double worst = 0.0, worstStep = 0.0;
  for (int y = 100; y < 160; ++y) {
    for (int x = 90; x < 150; ++x) {
      worst = std::max(worst, double(std::abs(field.at(x, y) - truth.at(x, y))));
      worstStep = std::max(worstStep, double(std::abs(field.at(x + 1, y) - field.at(x, y))));
    }
  }
  // The hole spans 60 m of height along x; a flat fill would be off by 30 m.
  EXPECT_LT(worst, 8.0);
  EXPECT_LT(worstStep, 4.0);  // no cliffs (the slope itself steps 1 m)
}

TEST(FillVoids, EdgeVoidsAndThinFields) {
  Heightfield row(10, 1);
  for (int x = 0; x < 10; ++x) row.at(x, 0) = float(x);
  row.at(0, 0) = kVoid;
  row.at(9, 0) = kVoid;
  EXPECT_EQ(fillVoids(row), 2);
  EXPECT_NEAR(row.at(0, 0), 1.0f, 1.0f);
  EXPECT_NEAR(row.at(9, 0), 8.0f, 1.0f);

  Heightfield column(1, 5);
  column.at(0, 0) = kVoid;
  column.at(0, 1) = 4.0f;
  column.at(0, 2) = kVoid;
  column.at(0, 3) = kVoid;
  column.at(0, 4) = 8.0f;
  EXPECT_EQ(fillVoids(column), 3);
  for (int y = 0; y < 5; ++y) {
    EXPECT_GE(column.at(0, y), 4.0f);
    EXPECT_LE(column.at(0, y), 8.0f);
  }
}

TEST(FillVoids, MostlyVoidLargeFieldIsFilledFromFewSamples) {
  Heightfield field(1024, 1024);
  for (float& h : field.heights) h = kVoid;
  field.at(0, 0) = 0.0f;
  field.at(1023, 1023) = 1000.0f;
  EXPECT_EQ(fillVoids(field), 1024 * 1024 - 2);
  EXPECT_EQ(countVoids(field), 0);
  EXPECT_LT(field.at(10, 10), field.at(1013, 1013));  // nearer the low sample, lower
}

}  // namespace
}  // namespace polder::terrain
