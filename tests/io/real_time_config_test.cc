// The `real_time:` block and the real-time transfer readers: values read, mistakes named.
#include <gtest/gtest.h>

#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/io/real_time_spec.h"
#include "hybridtest/io/run_spec_yaml.h"

namespace hybridtest::io {
namespace {

std::string Message(const std::string& text) {
  try {
    ReadRealTime(YamlInput::FromText(text, "rt.yaml"));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(RealTimeConfig, ReadsTheBlock) {
  const RealTimeSpec rt = ReadRealTime(YamlInput::FromText(
      "real_time: {hold_after_misses: 3, miss_tolerance: 0.0002, priority: 80, cpu: 1, "
      "lock_memory: false, force: true}\n", "rt.yaml"));
  EXPECT_TRUE(rt.enabled);
  EXPECT_EQ(rt.hold_after_misses, 3);
  EXPECT_DOUBLE_EQ(*rt.miss_tolerance, 0.0002);
  EXPECT_EQ(rt.priority, 80);
  EXPECT_EQ(rt.cpu, 1);
  EXPECT_FALSE(rt.lock_memory);
  EXPECT_TRUE(rt.force);
  EXPECT_FALSE(ReadRealTime(YamlInput::FromText("duration: 1\n", "rt.yaml")).enabled);
  EXPECT_TRUE(ReadRealTime(YamlInput::FromText("real_time: true\n", "rt.yaml")).enabled);
}

TEST(RealTimeConfig, NamesTheKeyThatIsWrong) {
  EXPECT_NE(Message("real_time: {priorty: 80}\n").find("priorty"), std::string::npos);
  EXPECT_NE(Message("real_time: {priority: 120}\n").find("real_time.priority"), std::string::npos);
  EXPECT_NE(Message("real_time: {force: maybe}\n").find("true or false"), std::string::npos);
  EXPECT_NE(Message("real_time: {clock: sundial}\n").find("real_time.clock"), std::string::npos);
}

TEST(RealTimeConfig, TheClockIsTheBlocksOrUnsetForTheDefault) {
  EXPECT_EQ(ReadRealTime(YamlInput::FromText("real_time: {clock: virtual}\n", "rt.yaml")).clock,
            "virtual");
  EXPECT_EQ(ReadRealTime(YamlInput::FromText("real_time: {clock: wall}\n", "rt.yaml")).clock,
            "wall");
  EXPECT_EQ(ReadRealTime(YamlInput::FromText("real_time: true\n", "rt.yaml")).clock, "");
}

TEST(RealTimeConfig, CompensatedNeedsItsInnerTransfer) {
  const std::string text =
      "model: {name: rotor, blades: 3}\n"
      "integrator: {scheme: alpha-os, dt: 0.001}\n"
      "duration: 0.01\n"
      "substructures:\n  r1:\n    type: physical\n    initial_stiffness: 7200\n"
      "    transfer: {type: compensated, method: ats}\n"
      "    safety: defaults\n";
  try {
    CompileRunSpec(ParseSimulationConfig(YamlInput::FromText(text, "rt.yaml")));
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("inner"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hybridtest::io
