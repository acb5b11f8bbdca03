// Small statistics over per-frame figures: percentiles, means, sums, maxima.
#pragma once

#include <span>

namespace polder {

struct Percentiles {
  double median = 0.0;
  double p99 = 0.0;
};

// Median and 99th percentile by nearest rank (the smallest value with at least that share of
// the values at or below it); zeros when there are none.
Percentiles percentiles(std::span<const double> values);

// Zero when there are no values.
double mean(std::span<const double> values);
double sum(std::span<const double> values);
double maximum(std::span<const double> values);

}  // namespace polder
