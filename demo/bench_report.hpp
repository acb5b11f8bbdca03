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

}  // namespace polder::cli
