#pragma once

#include <polder/cache/lru_cache.hpp>

namespace polder::cache {

// Share of lookups that found their entry (0 when there were none).
double hitRate(const CacheCounters& counters);

}  // namespace polder::cache
