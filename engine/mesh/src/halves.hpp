// Work split in two halves, each thread of a pair on its own (core::ThreadPool::runHalves).
#pragma once

#include <cstdint>
#include <utility>

namespace polder::mesh {

// The first (half 0) or second (half 1) half of the range [0, count).
inline std::pair<std::uint32_t, std::uint32_t> halfOf(std::uint32_t count, int half) {
  return half == 0 ? std::pair{0u, count / 2} : std::pair{count / 2, count};
}

}  // namespace polder::mesh
