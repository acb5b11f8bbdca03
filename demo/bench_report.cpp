#include "bench_report.hpp"

#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>

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

double currentRssMb() {
  std::ifstream statm("/proc/self/statm");
  long long sizePages = 0, residentPages = 0;
  if (!(statm >> sizePages >> residentPages)) return 0.0;
  return double(residentPages) * double(::sysconf(_SC_PAGESIZE)) / 1048576.0;
}

double residentMbInUse() {
  ::malloc_trim(0);
  return currentRssMb();
}

double heapInUseMb() {
  const struct mallinfo2 info = ::mallinfo2();
  return double(info.uordblks + info.hblkhd) / 1048576.0;
}

double rssDriftAfter(std::span<const RssSample> samples, int warmUpFrames) {
  double low = 0.0, high = 0.0;
  int count = 0;
  for (const RssSample& sample : samples) {
    if (sample.frame < warmUpFrames) continue;
    low = count == 0 ? sample.mb : std::min(low, sample.mb);
    high = count == 0 ? sample.mb : std::max(high, sample.mb);
    ++count;
  }
  return count < 2 || low <= 0.0 ? 0.0 : (high - low) / low;
}

}  // namespace polder::cli
