// Heap allocations made so far by this process, for tests that prove a steady frame
// allocates nothing. Link tests/support/allocation_counter.cpp into the test program: it
// replaces the global operator new and delete.
#pragma once

#include <cstddef>

namespace polder::test {

std::size_t allocationCount();

}  // namespace polder::test
