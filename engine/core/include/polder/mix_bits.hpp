// splitmix64's finaliser (S. Vigna): a cheap bijection of 64-bit values whose output bits all
// depend on every input bit. Hash tables use it to spread packed coordinates; the generator
// uses it to derive independent seeds.
#pragma once

#include <cstdint>

namespace polder {

constexpr std::uint64_t mixBits(std::uint64_t x) {
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

}  // namespace polder
