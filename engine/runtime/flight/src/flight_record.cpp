#include <polder/flight_record.hpp>

#include <algorithm>

namespace polder {
namespace {

double medianHostDataRatio(const FlightRecord& record) {
  std::vector<double> ratios;
  ratios.reserve(record.piecesMs.size());
  for (std::size_t i = 0; i < record.piecesMs.size(); ++i)
    ratios.push_back(record.piecesMs[i] / std::max(record.totalMs[i] - record.piecesMs[i], 1e-9));
  return percentiles(ratios).median;
}

}  // namespace

FlightSummary summarizeFlight(const FlightRecord& record) {
  FlightSummary summary;
  summary.trianglesMean = mean(record.triangles);
  summary.trianglesMax = maximum(record.triangles);
  summary.dikeTrianglesMean = mean(record.dikeTriangles);
  summary.visibleBlocksMean = mean(record.visibleBlocks);
  summary.culledBlocksMean = mean(record.culledBlocks);
  summary.cacheReuseRate = record.cacheLookups ? double(record.cacheHits) / double(record.cacheLookups) : 0.0;
  summary.selectMs = percentiles(record.selectMs);
  summary.lodMs = percentiles(record.lodMs);
  summary.dikesMs = percentiles(record.dikesMs);
  summary.piecesMs = percentiles(record.piecesMs);
  summary.totalMs = percentiles(record.totalMs);
  summary.pieceBytesPerFrame = record.pieceBytes / std::max(1, record.frames);
  summary.hostDataRatio = medianHostDataRatio(record);
  summary.drawn = !record.renderMs.empty();
  if (summary.drawn) {
    summary.renderMs = percentiles(record.renderMs);
    summary.uploadBytes = percentiles(record.uploadBytes);
    summary.uploadBytesMean = mean(record.uploadBytes);
    summary.framesUploadingNothing = std::size_t(std::count(record.uploadBytes.begin(), record.uploadBytes.end(), 0.0));
  }
  return summary;
}

CacheComparison compareCache(const FlightRecord& cached, const FlightRecord& uncached) {
  CacheComparison comparison;
  comparison.lodMsSavedFraction = 1.0 - sum(cached.lodMs) / std::max(sum(uncached.lodMs), 1e-12);
  comparison.totalMsSavedFraction = 1.0 - sum(cached.totalMs) / std::max(sum(uncached.totalMs), 1e-12);
  comparison.trianglesRatio = mean(cached.triangles) / std::max(mean(uncached.triangles), 1e-12);
  return comparison;
}

}  // namespace polder
