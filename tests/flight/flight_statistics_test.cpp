#include <polder/flight_record.hpp>
#include <polder/flight_statistics.hpp>

#include <algorithm>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace polder {
namespace {

TEST(FlightStatistics, PercentilesAreNearestRanks) {
  std::vector<double> values;
  for (int v = 100; v >= 1; --v) values.push_back(double(v));
  std::shuffle(values.begin(), values.end(), std::mt19937(7));
  const Percentiles p = percentiles(values);
  EXPECT_EQ(p.median, 50.0);  // 50 of the 100 values are at or below 50
  EXPECT_EQ(p.p99, 99.0);
  EXPECT_EQ(percentiles(std::vector<double>{4.0}).median, 4.0);
  EXPECT_EQ(percentiles(std::vector<double>{4.0}).p99, 4.0);
  const std::vector<double> three = {3.0, 1.0, 2.0};
  EXPECT_EQ(percentiles(three).median, 2.0);
  EXPECT_EQ(percentiles(three).p99, 3.0);
  EXPECT_EQ(three, (std::vector<double>{3.0, 1.0, 2.0}));  // the values are left as they were
  EXPECT_EQ(percentiles(std::vector<double>{}).median, 0.0);
  EXPECT_EQ(percentiles(std::vector<double>{}).p99, 0.0);
}

TEST(FlightStatistics, MeansSumsAndMaxima) {
  const std::vector<double> values = {2.0, -1.0, 5.0, 2.0};
  EXPECT_EQ(sum(values), 8.0);
  EXPECT_EQ(mean(values), 2.0);
  EXPECT_EQ(maximum(values), 5.0);
  EXPECT_EQ(mean(std::vector<double>{}), 0.0);
  EXPECT_EQ(maximum(std::vector<double>{}), 0.0);
}

FlightRecord knownRecord() {
  FlightRecord record;
  record.frames = 4;
  record.selectMs = {1.0, 2.0, 3.0, 4.0};
  record.lodMs = {2.0, 2.0, 2.0, 2.0};
  record.dikesMs = {0.5, 0.5, 0.5, 0.5};
  record.piecesMs = {1.0, 1.0, 3.0, 0.0};
  record.totalMs = {3.0, 5.0, 4.0, 6.0};  // the rest: 2, 4, 1, 6
  record.triangles = {100.0, 300.0, 200.0, 400.0};
  record.dikeTriangles = {10.0, 30.0, 20.0, 40.0};
  record.visibleBlocks = {4.0, 6.0, 4.0, 6.0};
  record.culledBlocks = {1.0, 1.0, 3.0, 3.0};
  record.cacheLookups = 40;
  record.cacheHits = 30;
  record.pieceBytes = 4096.0;
  return record;
}

TEST(FlightSummary, SummarisesTheRecord) {
  const FlightSummary summary = summarizeFlight(knownRecord());
  EXPECT_EQ(summary.trianglesMean, 250.0);
  EXPECT_EQ(summary.trianglesMax, 400.0);
  EXPECT_EQ(summary.dikeTrianglesMean, 25.0);
  EXPECT_EQ(summary.visibleBlocksMean, 5.0);
  EXPECT_EQ(summary.culledBlocksMean, 2.0);
  EXPECT_EQ(summary.cacheReuseRate, 0.75);
  EXPECT_EQ(summary.selectMs.median, 2.0);
  EXPECT_EQ(summary.selectMs.p99, 4.0);
  EXPECT_EQ(summary.totalMs.median, 4.0);
  EXPECT_EQ(summary.pieceBytesPerFrame, 1024.0);
  // Pieces against the rest, frame by frame: 0.5, 0.25, 3, 0; the median by nearest rank 0.25.
  EXPECT_EQ(summary.hostDataRatio, 0.25);
  EXPECT_FALSE(summary.drawn);
  EXPECT_EQ(summary.renderMs.median, 0.0);

  FlightRecord drawn = knownRecord();
  drawn.renderMs = {8.0, 9.0, 7.0, 10.0};
  drawn.uploadBytes = {1000.0, 0.0, 0.0, 200.0};
  const FlightSummary withDrawing = summarizeFlight(drawn);
  EXPECT_TRUE(withDrawing.drawn);
  EXPECT_EQ(withDrawing.renderMs.median, 8.0);
  EXPECT_EQ(withDrawing.renderMs.p99, 10.0);
  EXPECT_EQ(withDrawing.uploadBytesMean, 300.0);
  EXPECT_EQ(withDrawing.uploadBytes.median, 0.0);
  EXPECT_EQ(withDrawing.framesUploadingNothing, 2u);
  EXPECT_EQ(summarizeFlight(FlightRecord{}).cacheReuseRate, 0.0);
}

TEST(FlightSummary, ComparesTheCachedFlightWithTheUncached) {
  const FlightRecord cached = knownRecord();  // lod 8 ms, total 18 ms, 250 triangles a frame
  FlightRecord uncached = knownRecord();
  uncached.lodMs = {8.0, 8.0, 8.0, 8.0};
  uncached.totalMs = {6.0, 6.0, 6.0, 6.0};
  uncached.triangles = {200.0, 200.0, 200.0, 200.0};
  const CacheComparison comparison = compareCache(cached, uncached);
  EXPECT_DOUBLE_EQ(comparison.lodMsSavedFraction, 0.75);
  EXPECT_DOUBLE_EQ(comparison.totalMsSavedFraction, 0.25);
  EXPECT_DOUBLE_EQ(comparison.trianglesRatio, 1.25);
  const CacheComparison same = compareCache(cached, cached);
  EXPECT_EQ(same.lodMsSavedFraction, 0.0);
  EXPECT_EQ(same.trianglesRatio, 1.0);
}

}  // namespace
}  // namespace polder
