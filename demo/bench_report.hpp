// What the bench reports share: percentiles as JSON, and the process's peak memory.
#pragma once

#include <span>

#include <nlohmann/json.hpp>

#include <polder/flight_statistics.hpp>

namespace polder::cli {

// {"median": ..., "p99": ...} for a report.
nlohmann::json percentileJson(const Percentiles& percentiles);
nlohmann::json percentileJson(std::span<const double> values);

// The process's peak resident set size in MiB (getrusage; Linux reports KiB).
double peakRssMb();

// The process's resident set size now, in MiB (/proc/self/statm; 0 where unreadable).
double currentRssMb();

// Resident memory sampled during a run: the spread of the samples taken after warm-up, as a
// share of their smallest ((max - min) / min); 0 with fewer than two such samples.
struct RssSample {
  int frame = 0;
  double mb = 0.0;
};
double rssDriftAfter(std::span<const RssSample> samples, int warmUpFrames);

}  // namespace polder::cli
