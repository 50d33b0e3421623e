// UtcNowIso8601 (utc_time.h): the shape of the stamp and its agreement with the clock.
#include "hybridtest/io/utc_time.h"

#include <gtest/gtest.h>

#include <cctype>
#include <ctime>

namespace hybridtest::io {
namespace {

TEST(UtcTime, StampIsIso8601UtcToTheSecond) {
  const std::string stamp = UtcNowIso8601();
  ASSERT_EQ(stamp.size(), 20u) << stamp;  // YYYY-MM-DDTHH:MM:SSZ
  const std::string shape = "dddd-dd-ddTdd:dd:ddZ";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    if (shape[i] == 'd') {
      EXPECT_TRUE(std::isdigit(static_cast<unsigned char>(stamp[i]))) << stamp;
    } else {
      EXPECT_EQ(stamp[i], shape[i]) << stamp;
    }
  }
}

TEST(UtcTime, StampParsesBackToTheCurrentUtcTime) {
  const std::time_t before = std::time(nullptr);
  const std::string stamp = UtcNowIso8601();
  const std::time_t after = std::time(nullptr);
  std::tm utc{};
  ASSERT_NE(strptime(stamp.c_str(), "%Y-%m-%dT%H:%M:%SZ", &utc), nullptr) << stamp;
  const std::time_t parsed = timegm(&utc);  // read back as UTC, independent of TZ
  EXPECT_GE(parsed, before) << stamp;
  EXPECT_LE(parsed, after) << stamp;
}

}  // namespace
}  // namespace hybridtest::io
