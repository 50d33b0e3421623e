// Token handling (auth.h): constant-time comparison, token files, the per-address throttle.
#include "hybridtest/transfer/auth.h"

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
  EXPECT_NO_THROW(CheckBindPolicy("0.0.0.0", 7471, "s3cret", "the bench"));
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

}  // namespace
}  // namespace hybridtest::transfer
