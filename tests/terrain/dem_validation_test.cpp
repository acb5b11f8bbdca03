#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <polder/terrain/dem_validation.hpp>

namespace polder::terrain {
namespace {

TEST(CheckDemOptions, AcceptsDefaultsRejectsNonsense) {
  EXPECT_TRUE(checkDemOptions({}).ok());
  DemOptions options;
  options.zScale = -0.5;  // inverted heights are odd but legal
  EXPECT_TRUE(checkDemOptions(options).ok());

  for (double spacing : {0.0, -1.0, std::numeric_limits<double>::infinity(), std::nan("")}) {
    DemOptions bad;
    bad.spacingM = spacing;
    const Status status = checkDemOptions(bad);
    ASSERT_FALSE(status.ok()) << spacing;
    EXPECT_EQ(status.error().kind, ErrorKind::InvalidArgument);
    EXPECT_NE(status.error().message.find("spacing"), std::string::npos);
  }
  for (double scale : {0.0, std::numeric_limits<double>::infinity(), std::nan("")}) {
    DemOptions bad;
    bad.zScale = scale;
    const Status status = checkDemOptions(bad);
    ASSERT_FALSE(status.ok()) << scale;
    EXPECT_NE(status.error().message.find("height scale"), std::string::npos);
  }
  DemOptions badRaw;
  badRaw.raw = RawLayout{0, 5, SampleType::U16, false};
  EXPECT_FALSE(checkDemOptions(badRaw).ok());
}

TEST(CheckRasterSize, RefusesEmptyAbsurdAndOverBudget) {
  EXPECT_TRUE(checkRasterSize(4096, 4096, demBytesPerSample(2), 0).ok());

  // No samples, or one row or column: no ground to draw (InvalidData, with the size).
  for (const auto& [width, height] : std::vector<std::pair<int, int>>{{0, 100}, {1, 1}, {1, 500}, {500, 1}}) {
    const Status status = checkRasterSize(std::uint64_t(width), std::uint64_t(height), 4, 0);
    ASSERT_FALSE(status.ok()) << width << " x " << height;
    EXPECT_EQ(status.error().kind, ErrorKind::InvalidData);
    EXPECT_NE(status.error().message.find("at least 2 x 2"), std::string::npos) << status.error().message;
    EXPECT_NE(status.error().message.find(std::to_string(width) + " x " + std::to_string(height)), std::string::npos);
  }
  EXPECT_TRUE(checkRasterSize(2, 2, 4, 0).ok());

  Status status = checkRasterSize(0, 100, 4, 0);

  status = checkRasterSize(100000, 100000, 1, 0);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().kind, ErrorKind::OutOfMemory);
  EXPECT_NE(status.error().message.find("100000 x 100000"), std::string::npos) << status.error().message;
  EXPECT_NE(status.error().message.find("2147483648"), std::string::npos) << status.error().message;
  EXPECT_FALSE(checkRasterSize(4294967295u, 4294967295u, 1, 0).ok());

  status = checkRasterSize(1000, 1000, 10, 1 << 20);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().kind, ErrorKind::OutOfMemory);
  EXPECT_NE(status.error().message.find("memory limit of 1.0 MiB"), std::string::npos) << status.error().message;
  EXPECT_TRUE(checkRasterSize(1000, 1000, 10, 100 << 20).ok());

  ASSERT_GT(physicalMemoryBytes(), 0u);
  const std::uint64_t side = std::uint64_t(std::sqrt(double(physicalMemoryBytes()) / 8.0)) + 16;
  if (side * side <= kMaxDemSamples) {
    status = checkRasterSize(side, side, 16, 0);  // twice the machine's memory
    ASSERT_FALSE(status.ok());
    EXPECT_NE(status.error().message.find("physical memory"), std::string::npos) << status.error().message;
  }
}

TEST(FinishDem, SpacingPrecedenceRangeAndVoids) {
  Heightfield field(3, 2);
  field.heights = {1.0f, NAN, 3.0f, 4.0f, -2.0f, 6.0f};

  auto dem = finishDem(field, {}, {}, std::nullopt);
  ASSERT_TRUE(dem.ok());
  EXPECT_TRUE(dem->info.spacingAssumed);
  EXPECT_EQ(dem->field.spacingX, 1.0);
  EXPECT_EQ(dem->info.voids, 1);
  EXPECT_FALSE(std::isnan(dem->field.at(1, 0)));
  EXPECT_EQ(dem->info.minM, -2.0);
  EXPECT_EQ(dem->info.maxM, 6.0);

  dem = finishDem(field, {}, {}, GroundSpacing{30.0, 20.0});
  ASSERT_TRUE(dem.ok());
  EXPECT_FALSE(dem->info.spacingAssumed);
  EXPECT_EQ(dem->field.spacingX, 30.0);
  EXPECT_EQ(dem->field.spacingY, 20.0);

  DemOptions options;
  options.spacingM = 5.0;
  dem = finishDem(field, {}, options, GroundSpacing{30.0, 20.0});
  ASSERT_TRUE(dem.ok());
  EXPECT_EQ(dem->field.spacingX, 5.0);
  EXPECT_EQ(dem->field.spacingY, 5.0);
}

TEST(FinishDem, RejectsEmptyAndAllVoid) {
  auto dem = finishDem(Heightfield(), {}, {}, std::nullopt);
  ASSERT_FALSE(dem.ok());
  EXPECT_EQ(dem.error().kind, ErrorKind::InvalidData);
  EXPECT_NE(dem.error().message.find("at least 2 x 2"), std::string::npos);
  EXPECT_FALSE(finishDem(Heightfield(1, 9), {}, {}, std::nullopt).ok());

  Heightfield voids(4, 4);
  for (float& h : voids.heights) h = NAN;
  dem = finishDem(voids, {}, {}, std::nullopt);
  ASSERT_FALSE(dem.ok());
  EXPECT_EQ(dem.error().kind, ErrorKind::InvalidData);
  EXPECT_NE(dem.error().message.find("all 16 samples are no-data"), std::string::npos) << dem.error().message;
}

// Heights no terrain has (a height scale applied twice, say) are refused on either side;
// the deepest and highest real ground passes.
TEST(FinishDem, RejectsHeightsBeyondAnyTerrain) {
  for (const float extreme : {2e6f, -2e6f, 3e38f}) {
    Heightfield field(3, 3);
    field.at(1, 1) = extreme;
    const auto dem = finishDem(field, {}, {}, std::nullopt);
    ASSERT_FALSE(dem.ok()) << extreme;
    EXPECT_EQ(dem.error().kind, ErrorKind::InvalidData);
    EXPECT_NE(dem.error().message.find("height scale"), std::string::npos) << dem.error().message;
  }
  Heightfield real(3, 3);
  real.at(0, 0) = -10994.0f;  // Challenger Deep
  real.at(2, 2) = 8849.0f;    // Everest
  EXPECT_TRUE(finishDem(real, {}, {}, std::nullopt).ok());
}

}  // namespace
}  // namespace polder::terrain
