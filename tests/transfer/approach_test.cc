// Moves that do not reverse the load: the reversal counter, the actuator's monotone approach
// (input-shaped second-order lag) against the direct one, the emulated bench's count of force
// reversals per move, and the `approach` key of a bench file.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/actuator.h"
#include "hybridtest/transfer/bench_config.h"
#include "hybridtest/transfer/emulated_bench.h"
#include "hybridtest/transfer/reversal_counter.h"

namespace hybridtest::transfer {
namespace {

using ::testing::HasSubstr;

TEST(ReversalCounter, CountsChangesOfDirectionBeyondTheDeadbandOnly) {
  ReversalCounter c(0.1);
  c.Reset(0.0);
  for (double v : {0.05, 0.5, 1.0, 0.95, 1.2, 2.0}) c.Add(v);  // dips within the deadband
  EXPECT_EQ(c.count(), 0);
  c.Add(1.5);  // back by 0.5
  EXPECT_EQ(c.count(), 1);
  c.Add(1.0);
  c.Add(1.3);  // up again by 0.3
  EXPECT_EQ(c.count(), 2);
  c.Reset(5.0);
  for (double v : {4.0, 3.0, 3.05, 2.0}) c.Add(v);
  EXPECT_EQ(c.count(), 0);
}

// The positions of the actuator over `steps` internal steps toward `target` [m].
std::vector<double> Path(Actuator& a, double target, int steps) {
  std::vector<double> p;
  for (int i = 0; i < steps; ++i) {
    a.Step(target);
    p.push_back(a.position());
  }
  return p;
}

TEST(Actuator, MonotoneApproachNeverOvershootsWhereTheDirectOneDoes) {
  EmulatedBenchConfig config = DefaultEmulatedBenchConfig();  // second order, 10 Hz, ζ = 0.8
  for (const double zeta : {0.8, 0.5, 0.2}) {
    config.lag.damping_ratio = zeta;
    for (const double move : {2e-3, 1e-4, -5e-4}) {  // a ramp-limited and two short moves
      config.approach = Approach::kDirect;
      Actuator direct(config);
      const std::vector<double> d = Path(direct, move, 2000);
      const double direct_peak = move > 0 ? *std::max_element(d.begin(), d.end())
                                          : -*std::min_element(d.begin(), d.end());
      EXPECT_GT(direct_peak - std::abs(move), 1e-3 * std::abs(move)) << "ζ " << zeta;

      config.approach = Approach::kMonotone;
      Actuator monotone(config);
      const std::vector<double> p = Path(monotone, move, 2000);
      double previous = 0.0;
      for (std::size_t i = 0; i < p.size(); ++i) {
        // Moving one way only (to rounding).
        EXPECT_GE((p[i] - previous) * (move > 0 ? 1.0 : -1.0), -1e-12 * std::abs(move))
            << "ζ " << zeta << ", move " << move << ", step " << i;
        previous = p[i];
      }
      EXPECT_NEAR(p.back(), move, 1e-6 * std::abs(move)) << "ζ " << zeta;
      EXPECT_TRUE(monotone.reference_arrived(move));
    }
  }
}

TEST(EmulatedBench, CountsTheForceReversalsOfEveryMove) {
  EmulatedBenchConfig config = DefaultEmulatedBenchConfig();
  config.noise_std = 0.0;
  for (const Approach approach : {Approach::kDirect, Approach::kMonotone}) {
    config.approach = approach;
    EmulatedBench bench(config);
    bench.Activate();
    long reversals = 0;
    for (double command_mm : {1.0, 1.5, 0.5, -0.3, 0.2}) reversals += ExecuteOne(bench, command_mm).force_reversals;
    if (approach == Approach::kDirect) {
      EXPECT_GE(reversals, 5) << "an underdamped servo overshoots every move";
    } else {
      EXPECT_EQ(reversals, 0);
    }
  }
}

TEST(BenchConfig, ReadsTheApproachAndRefusesAnUnknownOne) {
  const YAML::Node ok = YAML::Load("{actuator: {approach: monotone}}");
  EXPECT_EQ(ParseEmulatedBenchConfig(ok, "t.yaml: bench").approach, Approach::kMonotone);
  // Without the key: monotone, what a pseudo-dynamic test needs.
  const YAML::Node none = YAML::Load("{actuator: {delay_ms: 2}}");
  EXPECT_EQ(ParseEmulatedBenchConfig(none, "t.yaml: bench").approach, Approach::kMonotone);
  const YAML::Node direct = YAML::Load("{actuator: {approach: direct}}");
  EXPECT_EQ(ParseEmulatedBenchConfig(direct, "t.yaml: bench").approach, Approach::kDirect);
  const YAML::Node bad = YAML::Load("{actuator: {approach: smooth}}");
  try {
    ParseEmulatedBenchConfig(bad, "t.yaml: bench");
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("actuator.approach"));
    EXPECT_THAT(e.what(), HasSubstr("monotone"));
  }
}

}  // namespace
}  // namespace hybridtest::transfer
