// What the bench reports share: percentiles as JSON, and the process's peak memory.
#pragma once

#include <cstdint>
#include <span>

#include <nlohmann/json.hpp>

#include <polder/flight_statistics.hpp>

namespace polder::cli {

// {"median": ..., "p99": ...} for a report.
nlohmann::json percentileJson(const Percentiles& percentiles);
nlohmann::json percentileJson(std::span<const double> values);

// The process's peak resident set size in MiB (getrusage; Linux reports KiB).
double peakRssMb();

// Budget mode's promise for one frame: at most the budget, and at least nine tenths of it.
inline bool endsWithinBudget(std::uint64_t triangles, std::uint64_t budget) {
  return triangles <= budget && triangles >= budget * 9 / 10;
}

// The process's resident set size now, in MiB (/proc/self/statm; 0 where unreadable).
double currentRssMb();
// The resident set size after handing the allocator's free pages back to the system
// (malloc_trim): the memory in use, without the pages kept from short-lived allocations such
// as a measurement's own ray-tracing scenes, which come and go between samples.
double residentMbInUse();
// Bytes allocated and not yet freed (glibc's mallinfo2): beside the RSS, it tells growth
// from the allocator holding on to freed memory.
double heapInUseMb();

// Resident memory sampled during a run: the spread of the samples taken after warm-up, as a
// share of their smallest ((max - min) / min); 0 with fewer than two such samples.
struct RssSample {
  int frame = 0;
  double mb = 0.0;
  double heapMb = 0.0;  // bytes the allocator has handed out and not had back
};
double rssDriftAfter(std::span<const RssSample> samples, int warmUpFrames);

}  // namespace polder::cli
