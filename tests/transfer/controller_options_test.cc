// The keys every acknowledging controller shares (transfer/controller_options.h): Modbus and ADS
// read them with one reader, so the same section gives the same options and the same errors.
#include "hybridtest/transfer/controller_options.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/ads/ads_config.h"
#include "hybridtest/transfer/modbus/modbus_config.h"

namespace hybridtest::transfer {
namespace {

// The shared keys of a transfer section, behind each protocol's own.
constexpr const char* kShared =
    "timeout: 7, response_timeout: 0.25, connect_timeout: 2, hold_timeout: 0.125, "
    "poll_interval: 0.001, plausibility: {position_tolerance: 0.5, force: 2000}, "
    "settle_tolerance: 0.02";

std::string More(const std::string& keys) { return keys.empty() ? "" : ", " + keys; }

ControllerOptions ReadModbus(const std::string& keys, const SafetyLimits* limits = nullptr) {
  const YamlInput in = YamlInput::FromText(
      "transfer: {type: modbus, host: h, map: {actuators: 2}" + More(keys) + "}",
      "run.yaml");
  return modbus::ParseModbusOptions(in, in.root()["transfer"], "transfer", {}, 3.0, limits);
}

ControllerOptions ReadAds(const std::string& keys, const SafetyLimits* limits = nullptr) {
  const YamlInput in = YamlInput::FromText(
      "transfer: {type: ads, host: 10.0.0.1, actuators: 2" + More(keys) + "}", "run.yaml");
  return ads::ParseAdsOptions(in, in.root()["transfer"], "transfer", {}, 3.0, limits);
}

template <typename Read>
std::string Error(Read read, const std::string& keys, const SafetyLimits* limits = nullptr) {
  try {
    read(keys, limits);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

void ExpectSame(const ControllerOptions& a, const ControllerOptions& b) {
  EXPECT_EQ(a.ack_timeout, b.ack_timeout);
  EXPECT_EQ(a.response_timeout, b.response_timeout);
  EXPECT_EQ(a.connect_timeout, b.connect_timeout);
  EXPECT_EQ(a.hold_timeout, b.hold_timeout);
  EXPECT_EQ(a.poll_interval, b.poll_interval);
  EXPECT_EQ(a.position_tolerance, b.position_tolerance);
  EXPECT_EQ(a.force_plausible, b.force_plausible);
  EXPECT_EQ(a.settle_tolerance, b.settle_tolerance);
  EXPECT_EQ(a.following_error, b.following_error);
  EXPECT_EQ(a.following_errors, b.following_errors);
}

TEST(ControllerOptions, ModbusAndAdsReadTheSameSectionAlike) {
  const ControllerOptions m = ReadModbus(std::string(kShared) + ", following_error: [0.1, 0.3]");
  ExpectSame(m, ReadAds(std::string(kShared) + ", following_error: [0.1, 0.3]"));
  EXPECT_EQ(m.ack_timeout, 7.0);
  EXPECT_EQ(m.response_timeout, 0.25);
  EXPECT_EQ(m.connect_timeout, 2.0);
  EXPECT_EQ(m.hold_timeout, 0.125);
  EXPECT_EQ(m.poll_interval, 0.001);
  EXPECT_EQ(*m.position_tolerance, 0.5);
  EXPECT_EQ(*m.force_plausible, 2000.0);
  EXPECT_EQ(*m.settle_tolerance, 0.02);
  EXPECT_EQ(*m.following_error, 0.1);
  EXPECT_EQ(m.following_errors, (std::vector<double>{0.1, 0.3}));

  // Defaults: the ack waits the slot's safety.timeout, an answer at most 1 s and never longer
  // than the ack; four settling windows of following error, at most the slot's max_increment.
  const ControllerOptions d = ReadModbus("");
  ExpectSame(d, ReadAds(""));
  EXPECT_EQ(d.ack_timeout, 3.0);
  EXPECT_EQ(d.response_timeout, 1.0);
  EXPECT_DOUBLE_EQ(*d.settle_tolerance, 0.05);  // [mm]
  EXPECT_DOUBLE_EQ(*d.following_error, 0.2);
  EXPECT_TRUE(d.following_errors.empty());
  EXPECT_EQ(ReadAds("timeout: 0.5").response_timeout, 0.5);
  SafetyLimits narrow;
  narrow.max_increment = 0.0001;  // [m]
  ExpectSame(ReadModbus("", &narrow), ReadAds("", &narrow));
  EXPECT_DOUBLE_EQ(*ReadAds("", &narrow).following_error, 0.1);  // capped [mm]
}

TEST(ControllerOptions, BadValuesGetTheSameMessageFromEitherProtocol) {
  SafetyLimits limits;  // ±150 mm stroke, 5 mm max_increment
  for (const std::string keys :
       {"timeout: 0", "response_timeout: -1", "poll_interval: -0.1",
        "plausibility: {force: 0}", "plausibility: {speed: 1}", "settle_tolerance: 6",
        "following_error: 400", "following_error: [0.1, 0.2, 0.3]", "following_error: [0.1, 0]"}) {
    const std::string modbus = Error(ReadModbus, keys, &limits);
    EXPECT_EQ(modbus, Error(ReadAds, keys, &limits)) << keys;
    EXPECT_EQ(modbus.rfind("run.yaml:1: transfer.", 0), 0u) << modbus;
  }
  const std::string wide = Error(ReadAds, "settle_tolerance: 6", &limits);
  EXPECT_NE(wide.find("6 mm is wider than the slot's safety.max_increment (5 mm)"),
            std::string::npos) << wide;
  const std::string stroke = Error(ReadAds, "following_error: 400", &limits);
  EXPECT_NE(stroke.find("400 mm is longer than the whole stroke"), std::string::npos) << stroke;
  EXPECT_NE(Error(ReadModbus, "following_error: [0.1, 0.2, 0.3]", &limits)
                .find("3 values for 2 actuators: give one limit per actuator, or one for all"),
            std::string::npos);
}

TEST(ControllerOptions, ResolvingFillsTheDefaultsInTheBenchUnitAndRefusesBadValues) {
  BenchUnits metres;  // SI
  ControllerOptions o;
  const auto limits = ResolveControllerOptions(o, metres, 3, "test transfer");
  ASSERT_EQ(limits.size(), 3u);
  EXPECT_DOUBLE_EQ(*o.position_tolerance, 1e-3);  // 1 mm
  EXPECT_DOUBLE_EQ(*o.force_plausible, 1e6);      // 1 MN
  EXPECT_DOUBLE_EQ(*o.settle_tolerance, 5e-5);
  for (const auto& l : limits) {
    EXPECT_DOUBLE_EQ(l.following_error, 2e-4);
    EXPECT_DOUBLE_EQ(l.settle_tolerance, 5e-5);
  }
  ControllerOptions per;
  per.following_errors = {1e-4, 2e-4, 3e-4};
  EXPECT_DOUBLE_EQ(ResolveControllerOptions(per, metres, 3, "t")[2].following_error, 3e-4);

  const auto message = [&](auto change) {
    ControllerOptions bad;
    change(bad);
    try {
      ResolveControllerOptions(bad, metres, 2, "test transfer");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(message([](ControllerOptions& b) { b.ack_timeout = 0.0; }),
            "test transfer: timeout = 0 s: expected a positive time");
  EXPECT_EQ(message([&](ControllerOptions& b) { b.hold_timeout = nan; }),
            "test transfer: hold_timeout = nan s: expected a positive time");
  EXPECT_NE(message([&](ControllerOptions& b) { b.poll_interval = -1.0; }).find("poll_interval = -1 s"),
            std::string::npos);
  EXPECT_NE(message([](ControllerOptions& b) { b.settle_tolerance = -1.0; })
                .find("settle_tolerance = -1 m"), std::string::npos);
  EXPECT_NE(message([](ControllerOptions& b) { b.following_errors = {1e-4}; })
                .find("1 following errors for 2 actuators"), std::string::npos);
  EXPECT_NE(message([&](ControllerOptions& b) { b.following_errors = {1e-4, nan}; })
                .find("following_error nan m"), std::string::npos);
  EXPECT_NE(message([](ControllerOptions& b) { b.following_error = 0.0; })
                .find("following_error 0 m"), std::string::npos);
}

}  // namespace
}  // namespace hybridtest::transfer
