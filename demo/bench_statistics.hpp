// Small statistics for benchmark reports.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

namespace polder::cli {

struct Percentiles {
  double median = 0.0;
  double p99 = 0.0;
};

// Median and 99th percentile (nearest rank) of the values; zeros when there are none.
Percentiles percentiles(std::vector<double> values);

double mean(const std::vector<double>& values);

// {"median": ..., "p99": ...} for a report.
nlohmann::json percentileJson(const std::vector<double>& values);

// The process's peak resident set size in MiB.
double peakRssMb();

}  // namespace polder::cli
