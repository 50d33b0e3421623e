#pragma once
// Counting heap allocations in tests (real-time code paths must not allocate).
//
// alloc_counter.cc replaces malloc/calloc/realloc in every test program with forwarders to
// glibc's own implementation (glibc supports replacing malloc) that count calls while counting
// is on. Eigen allocates with std::malloc and operator new calls malloc, so both are seen.
// Under AddressSanitizer (which owns malloc) or without glibc nothing can be counted:
// kCanCountAllocations is false and tests should GTEST_SKIP().
#include <utility>

namespace hybridtest::test_support {

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
inline constexpr bool kCanCountAllocations = true;
#else
inline constexpr bool kCanCountAllocations = false;
#endif

void StartCountingAllocations();
// Stops counting; returns the number of malloc/calloc/realloc calls since the start.
long StopCountingAllocations();

// Counts heap allocations made while `body` runs.
template <class Body>
long CountAllocations(Body&& body) {
  StartCountingAllocations();
  std::forward<Body>(body)();
  return StopCountingAllocations();
}

}  // namespace hybridtest::test_support
