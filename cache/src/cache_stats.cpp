#include <polder/cache/cache_stats.hpp>

namespace polder::cache {

double hitRate(const CacheCounters& counters) {
  const auto lookups = counters.hits + counters.misses;
  return lookups == 0 ? 0.0 : double(counters.hits) / double(lookups);
}

}  // namespace polder::cache
