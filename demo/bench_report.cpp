#include "bench_report.hpp"

#include <sys/resource.h>

namespace polder::cli {

nlohmann::json percentileJson(const Percentiles& percentiles) {
  return {{"median", percentiles.median}, {"p99", percentiles.p99}};
}

nlohmann::json percentileJson(std::span<const double> values) { return percentileJson(percentiles(values)); }

double peakRssMb() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

}  // namespace polder::cli
