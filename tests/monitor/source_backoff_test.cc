// SourceBackoff (monitor/source_backoff.h): failed attempts slow only their own source, the
// wait doubles up to its cap, a right token forgets, and the table stays bounded whatever the
// number of addresses.
#include <gtest/gtest.h>

#include "hybridtest/monitor/source_backoff.h"

namespace hybridtest::monitor {
namespace {

using std::chrono::milliseconds;
using Clock = SourceBackoff::Clock;

TEST(SourceBackoff, FreeFailuresThenAWaitThatDoublesUpToItsCap) {
  SourceBackoff b;
  const auto t0 = Clock::time_point{} + std::chrono::hours(1);
  for (int i = 0; i < SourceBackoff::kFreeFailures; ++i) {
    EXPECT_EQ(b.Failure("127.0.0.9", t0), Clock::duration::zero()) << i;
    EXPECT_EQ(b.Wait("127.0.0.9", t0), Clock::duration::zero());
  }
  EXPECT_EQ(b.Failure("127.0.0.9", t0), SourceBackoff::kFirstWait);
  EXPECT_EQ(b.Wait("127.0.0.9", t0 + milliseconds(400)), milliseconds(600));
  EXPECT_EQ(b.Failure("127.0.0.9", t0 + milliseconds(1000)), 2 * SourceBackoff::kFirstWait);
  auto t = t0 + milliseconds(1000);
  Clock::duration last{};
  for (int i = 0; i < 20; ++i) {
    t += std::chrono::seconds(61);
    last = b.Failure("127.0.0.9", t);
  }
  EXPECT_EQ(last, SourceBackoff::kMaxWait);
}

TEST(SourceBackoff, OtherSourcesAreNotSlowed) {
  SourceBackoff b;
  const auto t0 = Clock::time_point{} + std::chrono::hours(1);
  for (int i = 0; i < 50; ++i) b.Failure("127.0.0.2", t0);
  EXPECT_GT(b.Wait("127.0.0.2", t0), Clock::duration::zero());
  EXPECT_EQ(b.Wait("127.0.0.1", t0), Clock::duration::zero());
  EXPECT_EQ(b.Wait("127.0.0.3", t0), Clock::duration::zero());
  b.Success("127.0.0.2");
  EXPECT_EQ(b.Wait("127.0.0.2", t0), Clock::duration::zero());
}

TEST(SourceBackoff, AnIPv6SourceIsItsSlash64AndAMappedAddressItsIPv4) {
  EXPECT_EQ(SourceBackoff::SourceOf("::ffff:10.1.2.3"), "10.1.2.3");
  EXPECT_EQ(SourceBackoff::SourceOf("2001:db8:1:2:aaaa::1"),
            SourceBackoff::SourceOf("2001:db8:1:2:bbbb::7"));
  EXPECT_NE(SourceBackoff::SourceOf("2001:db8:1:2::1"), SourceBackoff::SourceOf("2001:db8:1:3::1"));
  EXPECT_EQ(SourceBackoff::SourceOf("127.0.0.7"), "127.0.0.7");
}

TEST(SourceBackoff, TheTableStaysBoundedWhateverTheNumberOfAddresses) {
  SourceBackoff b;
  auto t = Clock::time_point{} + std::chrono::hours(1);
  for (int i = 0; i < 3000; ++i) {
    t += milliseconds(1);
    b.Failure("10." + std::to_string(i / 65536) + "." + std::to_string((i / 256) % 256) + "." +
                  std::to_string(i % 256),
              t);
    ASSERT_LE(b.sources(), SourceBackoff::kMaxSources);
  }
  EXPECT_EQ(b.sources(), SourceBackoff::kMaxSources);
  // The most recent sources are still remembered.
  for (int i = 0; i < 3; ++i) b.Failure("10.0.11.183", t);
  EXPECT_GT(b.Failure("10.0.11.183", t), Clock::duration::zero());
}

}  // namespace
}  // namespace hybridtest::monitor
