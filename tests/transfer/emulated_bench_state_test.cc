// EmulatedBench::SaveState/RestoreState: a fresh bench of the same config, restored from a
// running bench's state, answers every later command bit for bit like the original (noise,
// lag, delay line and lab time included); Read() reports the position and force without
// moving or taking lab time.
#include <gtest/gtest.h>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/bench_config.h"
#include "hybridtest/transfer/emulated_bench.h"

namespace hybridtest::transfer {
namespace {

const std::string kExamples = std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/rotor/";

TEST(EmulatedBenchState, RestoredBenchContinuesBitIdentically) {
  const EmulatedBenchConfig config = LoadEmulatedBenchConfig(kExamples + "bench-cantilever.yaml");
  EmulatedBench original(config);
  original.Activate();
  for (int k = 1; k <= 5; ++k) ExecuteOne(original, 0.5 * k);  // [mm]
  // Through text, as in the run state file.
  const auto saved = nlohmann::json::parse(original.SaveState().dump());
  EmulatedBench restored(config);
  restored.Activate();
  restored.RestoreState(saved);
  EXPECT_EQ(restored.command_count(), original.command_count());
  for (int k = 1; k <= 5; ++k) {
    const Measurement a = ExecuteOne(original, 2.5 - 0.3 * k);
    const Measurement b = ExecuteOne(restored, 2.5 - 0.3 * k);
    EXPECT_EQ(b.position, a.position) << k;
    EXPECT_EQ(b.force, a.force) << k;  // the noise generator continues where it was
    EXPECT_EQ(b.lab_time, a.lab_time) << k;
  }
  // A fresh bench without the state would not: the noise differs.
  EmulatedBench fresh(config);
  fresh.Activate();
  EXPECT_NE(ExecuteOne(fresh, 1.5).force, ExecuteOne(original, 1.5).force);
}

TEST(EmulatedBenchState, ReadDoesNotMove) {
  EmulatedBench bench(LoadEmulatedBenchConfig(kExamples + "bench-ideal.yaml"));
  bench.Activate();
  const Measurement m = ExecuteOne(bench, 23.0);  // [mm]; p0 = 20 mm, k = 7200 N/m
  const auto read = ReadOne(bench);
  ASSERT_TRUE(read.has_value());
  EXPECT_DOUBLE_EQ(read->position, 23.0);
  EXPECT_NEAR(read->force, 7200.0 * 0.003, 1e-9);
  EXPECT_EQ(read->lab_time, m.lab_time);
  EXPECT_EQ(bench.command_count(), 1);
}

TEST(EmulatedBenchState, ForeignStateIsRefused) {
  EmulatedBench bench(LoadEmulatedBenchConfig(kExamples + "bench-ideal.yaml"));
  EXPECT_THROW(bench.RestoreState(nlohmann::json{{"kind", "remote"}}), Error);
  EXPECT_THROW(bench.RestoreState(nlohmann::json{{"kind", "emulated"}}), Error);
}

}  // namespace
}  // namespace hybridtest::transfer
