// Token handling (auth.h): constant-time comparison, token files, the per-address throttle.
#include "hybridtest/transfer/auth.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {
namespace {

TEST(Auth, BindPolicyNeedsATokenOffLoopback) {
  EXPECT_NO_THROW(CheckBindPolicy("127.0.0.1", 7471, "", "the bench"));
  EXPECT_NO_THROW(CheckBindPolicy("::1", 7471, "", "the bench"));
  EXPECT_NO_THROW(CheckBindPolicy("0.0.0.0", 7471, "0123456789abcdef", "the bench"));
  try {
    CheckBindPolicy("0.0.0.0", 8090, "", "the OpenFresco bench");
    FAIL() << "a non-loopback address without a token was accepted";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("the OpenFresco bench on 0.0.0.0:8090 without a token"),
              std::string::npos) << what;
    EXPECT_NE(what.find(kTokenEnvironmentVariable), std::string::npos) << what;
  }
}

// Issue 15: a token of one space, or a short one, passed the off-loopback bind policy.
TEST(Auth, BindPolicyRefusesShortAndWhitespaceTokensOffLoopback) {
  const auto error = [](const std::string& host, const std::string& token) -> std::string {
    try {
      CheckBindPolicy(host, 7471, token, "the bench");
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_NE(error("0.0.0.0", " ").find("only whitespace"), std::string::npos);
  EXPECT_NE(error("0.0.0.0", std::string(20, ' ')).find("only whitespace"), std::string::npos);
  EXPECT_NE(error("0.0.0.0", "\t \t").find("only whitespace"), std::string::npos);
  EXPECT_NE(error("127.0.0.1", " ").find("only whitespace"), std::string::npos);  // anywhere
  const std::string short_token = error("0.0.0.0", "s3cret");
  EXPECT_NE(short_token.find("a token of 6 bytes"), std::string::npos) << short_token;
  EXPECT_NE(short_token.find("at least 16 bytes"), std::string::npos) << short_token;
  EXPECT_NE(error("0.0.0.0", std::string(15, 'x')).find("15 bytes"), std::string::npos);
  EXPECT_EQ(error("0.0.0.0", std::string(16, 'x')), "accepted");
  EXPECT_EQ(error("127.0.0.1", "s3cret"), "accepted");  // loopback: any real token
  EXPECT_EQ(error("::1", ""), "accepted");
}

TEST(Auth, TokensEqualComparesEveryByteAndTheLength) {
  EXPECT_TRUE(TokensEqual("s3cret", "s3cret"));
  EXPECT_TRUE(TokensEqual("", ""));
  EXPECT_FALSE(TokensEqual("s3cret", "s3creT"));
  EXPECT_FALSE(TokensEqual("s3cret", "s3cre"));   // a prefix is not enough
  EXPECT_FALSE(TokensEqual("s3cre", "s3cret"));
  EXPECT_FALSE(TokensEqual("", "x"));
  EXPECT_FALSE(TokensEqual(std::string("a\0b", 3), std::string("a\0c", 3)));
}

TEST(Auth, TokenFileGivesItsFirstLineAndRefusesAnEmptyOne) {
  const auto dir = std::filesystem::temp_directory_path() / "hybridtest_auth_test";
  std::filesystem::create_directories(dir);
  const auto path = (dir / "token").string();
  std::ofstream(path) << "s3cret  \nsecond line\n";
  EXPECT_EQ(ReadTokenFile(path, "--token-file"), "s3cret");
  std::ofstream(path) << "\n";
  try {
    ReadTokenFile(path, "--token-file");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--token-file"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadTokenFile((dir / "missing").string(), "x"), ConfigError);
  std::ofstream(path) << std::string(kMaxTokenBytes + 1, 'a');
  EXPECT_THROW(ReadTokenFile(path, "x"), ConfigError);
  std::filesystem::remove_all(dir);
}

TEST(Auth, ThrottleLocksOneAddressAfterFiveFailuresAndReleasesIt) {
  AuthThrottle throttle;
  const auto t0 = AuthThrottle::Clock::time_point{} + std::chrono::hours(1);
  for (int i = 1; i < AuthThrottle::kMaxFailures; ++i) {
    EXPECT_FALSE(throttle.RecordFailure("10.0.0.9", t0));
    EXPECT_FALSE(throttle.IsLocked("10.0.0.9", t0));
  }
  EXPECT_TRUE(throttle.RecordFailure("10.0.0.9", t0));  // the fifth
  EXPECT_TRUE(throttle.IsLocked("10.0.0.9", t0 + std::chrono::seconds(59)));
  EXPECT_FALSE(throttle.IsLocked("127.0.0.1", t0));  // other addresses are not affected
  EXPECT_FALSE(throttle.IsLocked("10.0.0.9", t0 + AuthThrottle::kLockout));
}

TEST(Auth, FailuresOutsideTheWindowDoNotAddUp) {
  AuthThrottle throttle;
  auto t = AuthThrottle::Clock::time_point{} + std::chrono::hours(1);
  for (int i = 0; i < 3 * AuthThrottle::kMaxFailures; ++i) {
    EXPECT_FALSE(throttle.RecordFailure("h", t));
    t += AuthThrottle::kFailureWindow / (AuthThrottle::kMaxFailures - 1) +
         std::chrono::seconds(1);
  }
}

TEST(Auth, AddressBlocksAreIpv4Slash24AndIpv6Slash64) {
  EXPECT_EQ(AddressBlock("127.0.0.1"), "127.0.0.0/24");
  EXPECT_EQ(AddressBlock("127.0.0.254"), "127.0.0.0/24");
  EXPECT_EQ(AddressBlock("10.1.2.3"), "10.1.2.0/24");
  EXPECT_NE(AddressBlock("10.1.3.3"), AddressBlock("10.1.2.3"));
  EXPECT_EQ(AddressBlock("::ffff:10.1.2.3"), "10.1.2.0/24");  // IPv4-mapped: its IPv4 block
  EXPECT_EQ(AddressBlock("2001:db8:0:1::5"), "2001:db8:0:1::/64");
  EXPECT_EQ(AddressBlock("2001:db8:0:1:ffff:1:2:3"), "2001:db8:0:1::/64");
  EXPECT_NE(AddressBlock("2001:db8:0:2::5"), AddressBlock("2001:db8:0:1::5"));
  EXPECT_EQ(AddressBlock("::1"), "::/64");
  EXPECT_EQ(AddressBlock("unknown"), "unknown");
}

// Issue 15: rotating 127.0.0.x source addresses gave thousands of guesses per second.
TEST(Auth, RotatingAddressesInOneBlockAreLockedOutTogether) {
  AuthThrottle throttle;
  const auto t0 = AuthThrottle::Clock::time_point{} + std::chrono::hours(1);
  for (int i = 1; i < AuthThrottle::kMaxFailures; ++i) {
    EXPECT_FALSE(throttle.RecordFailure(fmt::format("127.0.0.{}", i), t0));
  }
  EXPECT_TRUE(throttle.RecordFailure("127.0.0.99", t0));
  EXPECT_TRUE(throttle.IsLocked("127.0.0.200", t0));  // a fresh address of the same /24
  EXPECT_EQ(throttle.Check("127.0.0.7", t0), AuthThrottle::Verdict::kBlockLocked);
  EXPECT_FALSE(throttle.IsLocked("127.0.1.1", t0));   // another /24
  for (int i = 1; i < AuthThrottle::kMaxFailures; ++i) {
    EXPECT_FALSE(throttle.RecordFailure(fmt::format("2001:db8::{:x}", i), t0));
  }
  EXPECT_TRUE(throttle.RecordFailure("2001:db8::ffff:1", t0));
  EXPECT_TRUE(throttle.IsLocked("2001:db8::1234:5678:9abc", t0));  // the same /64
  EXPECT_FALSE(throttle.IsLocked("2001:db8:0:1::1", t0));
  const std::string text =
      AuthThrottle::RefusalText(AuthThrottle::Verdict::kBlockLocked, "127.0.0.7");
  EXPECT_NE(text.find("127.0.0.0/24"), std::string::npos) << text;
}

TEST(Auth, GlobalBudgetBoundsGuessesSpreadOverManyBlocks) {
  AuthThrottle throttle;
  auto t = AuthThrottle::Clock::time_point{} + std::chrono::hours(1);
  // Every guess from a fresh /24: no block ever locks, the global budget still runs out.
  int allowed = 0;
  for (int i = 0; i < 1000; ++i) {
    const std::string peer = fmt::format("10.{}.{}.1", i / 256, i % 256);
    if (throttle.Check(peer, t) != AuthThrottle::Verdict::kAllowed) continue;
    ++allowed;
    EXPECT_FALSE(throttle.RecordFailure(peer, t));
  }
  EXPECT_EQ(allowed, AuthThrottle::kGlobalBurst);
  EXPECT_TRUE(throttle.IsRateLimited(t));
  EXPECT_EQ(throttle.Check("192.168.7.7", t), AuthThrottle::Verdict::kRateLimited);
  EXPECT_NE(AuthThrottle::RefusalText(AuthThrottle::Verdict::kRateLimited, "x")
                .find("rate limit"),
            std::string::npos);
  // It refills at one failure per kGlobalRefill: a guesser gets about one guess per second.
  t += AuthThrottle::kGlobalRefill;
  EXPECT_EQ(throttle.Check("192.168.7.7", t), AuthThrottle::Verdict::kAllowed);
  throttle.RecordFailure("192.168.7.7", t);
  EXPECT_EQ(throttle.Check("192.168.7.8", t), AuthThrottle::Verdict::kRateLimited);
  // A full refill after kGlobalBurst × kGlobalRefill.
  t += AuthThrottle::kGlobalBurst * AuthThrottle::kGlobalRefill;
  allowed = 0;
  for (int i = 0; i < 100; ++i) {
    const std::string peer = fmt::format("172.16.{}.1", i);
    if (throttle.Check(peer, t) != AuthThrottle::Verdict::kAllowed) break;
    ++allowed;
    throttle.RecordFailure(peer, t);
  }
  EXPECT_EQ(allowed, AuthThrottle::kGlobalBurst);
  EXPECT_EQ(throttle.failures(), 2 * AuthThrottle::kGlobalBurst + 1);
}

}  // namespace
}  // namespace hybridtest::transfer
