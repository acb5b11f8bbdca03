#include <polder/flight_statistics.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace polder {

Percentiles percentiles(std::span<const double> values) {
  if (values.empty()) return {};
  std::vector<double> sorted(values.begin(), values.end());
  auto rank = [&](double q) {
    const std::size_t index = std::min(sorted.size() - 1, std::size_t(std::ceil(q * double(sorted.size()))) - 1);
    std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(index), sorted.end());
    return sorted[index];
  };
  Percentiles result;
  result.median = rank(0.5);
  result.p99 = rank(0.99);
  return result;
}

double mean(std::span<const double> values) { return values.empty() ? 0.0 : sum(values) / double(values.size()); }

double sum(std::span<const double> values) {
  double total = 0.0;
  for (double v : values) total += v;
  return total;
}

double maximum(std::span<const double> values) {
  return values.empty() ? 0.0 : *std::max_element(values.begin(), values.end());
}

}  // namespace polder
