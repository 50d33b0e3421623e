// SpscRing (runner/spsc_ring.h), as the monitor and the real-time queue use it: slots made
// once, order kept, a full ring refuses (the producer counts its drops), and a concurrent
// consumer sees every kept frame whole and in order.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "hybridtest/runner/spsc_ring.h"

namespace hybridtest::runner {
namespace {

using Frames = SpscRing<std::vector<double>>;

TEST(SpscRing, KeepsOrderAndAFullRingRefuses) {
  Frames ring(4, [] { return std::vector<double>(2); });
  EXPECT_EQ(ring.capacity(), 4u);
  int dropped = 0;
  for (int i = 0; i < 6; ++i) {
    std::vector<double>* f = ring.Claim();
    if (f == nullptr) {
      ++dropped;
      continue;
    }
    (*f)[0] = i;
    (*f)[1] = 10 * i;
    ring.Publish();
  }
  EXPECT_EQ(dropped, 2);
  EXPECT_EQ(ring.free_slots(), 0u);
  std::vector<double> seen;
  while (const std::vector<double>* f = ring.Front()) {
    EXPECT_EQ((*f)[1], 10 * (*f)[0]);
    seen.push_back((*f)[0]);
    ring.Pop();
  }
  EXPECT_EQ(seen, (std::vector<double>{0, 1, 2, 3}));
  EXPECT_TRUE(ring.empty());
  EXPECT_EQ(ring.free_slots(), 4u);
}

TEST(SpscRing, AConcurrentConsumerSeesEveryKeptFrameWholeAndInOrder) {
  Frames ring(64, [] { return std::vector<double>(3); });
  constexpr int kFrames = 200000;
  std::atomic<long> dropped{0};
  std::atomic<bool> done{false};
  std::thread producer([&] {
    for (int i = 0; i < kFrames; ++i) {
      if (std::vector<double>* f = ring.Claim()) {
        (*f)[0] = i;
        (*f)[1] = -i;
        (*f)[2] = 2.0 * i;
        ring.Publish();
      } else {
        dropped.fetch_add(1);
      }
    }
    done.store(true);
  });
  long kept = 0;
  double last = -1;
  bool whole = true, ordered = true;
  auto drain = [&] {
    while (const std::vector<double>* f = ring.Front()) {
      whole = whole && (*f)[1] == -(*f)[0] && (*f)[2] == 2.0 * (*f)[0];
      ordered = ordered && (*f)[0] > last;
      last = (*f)[0];
      ++kept;
      ring.Pop();
    }
  };
  while (!done.load()) drain();
  producer.join();
  drain();
  EXPECT_TRUE(whole);
  EXPECT_TRUE(ordered);
  EXPECT_EQ(kept + dropped.load(), kFrames);
}

}  // namespace
}  // namespace hybridtest::runner
