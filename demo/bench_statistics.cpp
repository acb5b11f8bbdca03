#include "bench_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <sys/resource.h>

namespace polder::cli {

Percentiles percentiles(std::vector<double> values) {
  if (values.empty()) return {};
  auto rank = [&](double q) {
    const std::size_t index = std::min(values.size() - 1, std::size_t(std::ceil(q * double(values.size()))) - 1);
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(index), values.end());
    return values[index];
  };
  Percentiles result;
  result.median = rank(0.5);
  result.p99 = rank(0.99);
  return result;
}

double mean(const std::vector<double>& values) {
  if (values.empty()) return 0.0;
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / double(values.size());
}

nlohmann::json percentileJson(const std::vector<double>& values) {
  const Percentiles p = percentiles(values);
  return {{"median", p.median}, {"p99", p.p99}};
}

double peakRssMb() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

}  // namespace polder::cli
