#include "hybridtest/transfer/bench_config.h"

#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kExamples = std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/rotor/";

EmulatedBenchConfig Parse(const std::string& text) {
  return ParseEmulatedBenchConfig(YAML::Load(text), "t.yaml: bench");
}

std::string ErrorOf(const std::string& text) {
  try {
    Parse(text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(BenchConfig, DefaultsAreThePapersBench) {
  const EmulatedBenchConfig c = Parse("{}");
  EXPECT_NEAR(c.specimen->initial_stiffness(), 5250.0, 1e-9);
  EXPECT_DOUBLE_EQ(c.position_max - c.position_min, 0.300);
  EXPECT_DOUBLE_EQ(c.capacity, 10e3);
  EXPECT_EQ(c.units.length_name, "mm");
  EXPECT_EQ(c.units.force_name, "N");
  EXPECT_DOUBLE_EQ(c.safety.force_hard, 10e3);
  EXPECT_FALSE(c.realtime);
}

TEST(BenchConfig, KeysAreConvertedToSI) {
  const EmulatedBenchConfig c = Parse(R"(
units: {length: m, force: kN}
pacing: realtime
seed: 42
p0_mm: 12.5
specimen: {type: linear, stiffness: 7200}
actuator: {velocity_limit_mm_per_s: 50, delay_ms: 3, lag: {type: first_order, time_constant_ms: 15}}
load_cell: {noise_std_N: 0.5, resolution_N: 0.02, offset_N: 1}
settling: {tolerance_mm: 0.01, dwell_ms: 50}
sampling: {window_ms: 200}
timing: {overhead_ms: 300, internal_step_ms: 0.5}
safety: {max_increment_mm: 2, force_soft_kN: 1, force_hard_kN: 2, timeout_s: 3}
faults: [{at: 5, kind: spike, force_N: 1000}]
)");
  EXPECT_DOUBLE_EQ(c.units.newtons_per_force_unit, 1e3);
  EXPECT_DOUBLE_EQ(c.units.metres_per_length_unit, 1.0);
  EXPECT_TRUE(c.realtime);
  EXPECT_EQ(c.seed, 42u);
  EXPECT_DOUBLE_EQ(c.p0, 0.0125);
  EXPECT_DOUBLE_EQ(c.initial_position, 0.0125);
  EXPECT_DOUBLE_EQ(c.velocity_limit, 0.05);
  EXPECT_DOUBLE_EQ(c.delay, 0.003);
  EXPECT_EQ(c.lag.type, ServoLag::Type::kFirstOrder);
  EXPECT_DOUBLE_EQ(c.lag.time_constant, 0.015);
  EXPECT_DOUBLE_EQ(c.noise_std, 0.5);
  EXPECT_DOUBLE_EQ(c.settle_tolerance, 1e-5);
  EXPECT_DOUBLE_EQ(c.settle_dwell, 0.05);
  EXPECT_DOUBLE_EQ(c.sampling_window, 0.2);
  EXPECT_DOUBLE_EQ(c.overhead, 0.3);
  EXPECT_DOUBLE_EQ(c.internal_step, 0.0005);
  EXPECT_DOUBLE_EQ(c.safety.max_increment, 0.002);
  EXPECT_DOUBLE_EQ(c.safety.force_soft, 1e3);
  ASSERT_EQ(c.faults.size(), 1u);
  EXPECT_EQ(c.faults[0].kind, FaultKind::kSpike);
  EXPECT_DOUBLE_EQ(c.faults[0].spike_force, 1000.0);
  EXPECT_EQ(c.faults[0].command, 5);
}

TEST(BenchConfig, ErrorsNameTheKeyPathAndTheFix) {
  EXPECT_THAT(ErrorOf("{units: {length: inch}}"),
              AllOf(HasSubstr("t.yaml: bench.units.length"), HasSubstr("mm or m")));
  EXPECT_THAT(ErrorOf("{actuator: {delay_ms: soon}}"),
              AllOf(HasSubstr("bench.actuator.delay_ms"), HasSubstr("'soon'"),
                    HasSubstr("delay in ms")));
  EXPECT_THAT(ErrorOf("{actuator: {stroke_mm: 300}}"),
              AllOf(HasSubstr("bench.actuator.stroke_mm"), HasSubstr("unknown key"),
                    HasSubstr("position_min_mm")));
  EXPECT_THAT(ErrorOf("{safety: {stroke_max_mm: 200}}"), HasSubstr("exceeds the actuator range"));
  EXPECT_THAT(ErrorOf("{faults: [{at: 1, kind: gremlin}]}"),
              AllOf(HasSubstr("bench.faults[0].kind"), HasSubstr("nan, inf, spike, silence")));
  EXPECT_THAT(ErrorOf("{specimen: {type: linear}}"), HasSubstr("bench.specimen.stiffness"));
  EXPECT_THAT(ErrorOf("{pacing: fast}"), HasSubstr("accelerated or realtime"));
  EXPECT_THAT(ErrorOf("{actuator: {lag: {type: second_order, natural_frequency_hz: 100}}}"),
              HasSubstr("too fast for timing.internal_step_ms"));
  EXPECT_THAT(ErrorOf("{safety: {force_soft_kN: 12}}"), HasSubstr("force_soft"));
}

// Timing keys that would make one command simulate for hours (and ignore Ctrl-C) are refused.
TEST(BenchConfig, EveryTimingKeyIsBounded) {
  EXPECT_THAT(ErrorOf("{timing: {internal_step_ms: 1e-300}}"),
              AllOf(HasSubstr("timing.internal_step_ms"), HasSubstr("0.001 to 100 ms")));
  EXPECT_THAT(ErrorOf("{sampling: {window_ms: 1e12}}"),
              AllOf(HasSubstr("sampling.window_ms"), HasSubstr("0 to 60000 ms")));
  EXPECT_THAT(ErrorOf("{settling: {dwell_ms: 1e9}}"), HasSubstr("settling.dwell_ms"));
  EXPECT_THAT(ErrorOf("{actuator: {delay_ms: 1e6}}"), HasSubstr("actuator.delay_ms"));
  EXPECT_THAT(ErrorOf("{timing: {overhead_ms: 1e10}}"), HasSubstr("timing.overhead_ms"));
  EXPECT_THAT(ErrorOf("{timing: {internal_step_ms: 0.001}, sampling: {window_ms: 30000}}"),
              HasSubstr("more than 10 million internal steps"));
  EXPECT_EQ(ErrorOf("{timing: {internal_step_ms: 0.5}, sampling: {window_ms: 500}}"),
            "(no error)");
}

TEST(BenchConfig, LoadFileErrors) {
  EXPECT_THROW(LoadEmulatedBenchConfig("/nonexistent/bench.yaml"), ConfigError);
  const std::string path = ::testing::TempDir() + "/not_a_bench.yaml";
  std::ofstream(path) << "integrator: {dt: 0.001}\n";
  try {
    LoadEmulatedBenchConfig(path);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("unknown key 'integrator'"), HasSubstr("expected one of: bench, openfresco")));
  }
}

TEST(BenchConfig, ExamplesLoad) {
  const auto ideal = LoadEmulatedBenchConfig(kExamples + "bench-ideal.yaml");
  EXPECT_DOUBLE_EQ(ideal.specimen->initial_stiffness(), 7200.0);
  EXPECT_EQ(ideal.lag.type, ServoLag::Type::kNone);
  EXPECT_DOUBLE_EQ(ideal.noise_std, 0.0);
  const auto cantilever = LoadEmulatedBenchConfig(kExamples + "bench-cantilever.yaml");
  EXPECT_NEAR(cantilever.specimen->initial_stiffness(), 5250.0, 1e-9);
  EXPECT_GT(cantilever.noise_std, 0.0);
}

}  // namespace
}  // namespace hybridtest::transfer

namespace hybridtest::transfer {
namespace {

TEST(BenchConfigLimits, SeedAndFaultIndexAreRangeChecked) {
  EXPECT_THAT(ErrorOf("{seed: 1e30}"), AllOf(HasSubstr("bench.seed"), HasSubstr("from 0 to")));
  EXPECT_THAT(ErrorOf("{seed: -1}"), HasSubstr("bench.seed"));
  EXPECT_THAT(ErrorOf("{faults: [{at: 1e30, kind: nan}]}"),
              AllOf(HasSubstr("bench.faults[0].at"), HasSubstr("from 1 to")));
  EXPECT_THAT(ErrorOf("{faults: [{at: 0, kind: nan}]}"), HasSubstr("1-based"));
  EXPECT_EQ(Parse("{seed: 9007199254740992}").seed, 9007199254740992ul);
}

TEST(BenchConfigLimits, OneFaultInjectorWithOneIndexingConvention) {
  const EmulatedBenchConfig c = Parse("{faults: [{at: 3, kind: inf}, {at: 4, kind: spike}]}");
  ASSERT_EQ(c.faults.size(), 2u);
  EXPECT_EQ(c.faults[0].kind, FaultKind::kInf);
  EXPECT_EQ(c.faults[0].command, 3);  // the same 1-based N as `--inject inf@3`
  EXPECT_EQ(c.faults[1].spike_force, kDefaultSpikeForce);
  EXPECT_THAT(ErrorOf("{faults: [{at: 1, kind: corrupt}]}"),
              AllOf(HasSubstr("bench.faults[0].kind"), HasSubstr("--inject")));
}

}  // namespace
}  // namespace hybridtest::transfer

namespace hybridtest::transfer {
namespace {

// Found by fuzz/bench_config_fuzz.cc: an absent `bench:` (an invalid node of a const mapping)
// escaped as YAML::InvalidNode (exit 70) instead of a ConfigError.
TEST(BenchConfigLimits, AnAbsentBenchNodeIsAConfigError) {
  const YAML::Node root = YAML::Load("benc: {seed: 1}");
  const YAML::Node& const_root = root;
  EXPECT_THROW(ParseEmulatedBenchConfig(const_root["bench"], "t.yaml: bench"), ConfigError);
}

}  // namespace
}  // namespace hybridtest::transfer
