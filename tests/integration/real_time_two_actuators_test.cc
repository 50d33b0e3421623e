// The two-actuator blade in real time (issue 46; examples/06_blade_two_actuators/real-time.yaml):
//   - on the built-in servo-hydraulic plant of two actuators with ATS on each, in virtual time,
//     it exits 0 with J2 ≤ 1 % for each actuator, and the sidecar carries J1–J3 per actuator
//     and per slot;
//   - with an ideal plant (zero delay) and no compensation, the same specimen paced in virtual
//     time equals its pseudo-dynamic run (the same config without `real_time:`) within 1e-9 m.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "hybridtest/io/run_reader.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;
using testing::RunCommand;

const std::string kSource = HYBRIDTEST_SOURCE_DIR;
const std::string kBinary = HYBRIDTEST_BINARY;
const std::string kExample = kSource + "/examples/06_blade_two_actuators/real-time.yaml";

std::pair<int, std::string> RunBlade(const std::string& config, const fs::path& out,
                                const std::string& clock) {
  return RunCommand(fmt::format("{} run {} {} --out {} --quiet 2>&1", kBinary, config,
                                clock.empty() ? "" : "--clock " + clock, out.string()), 120);
}

TEST(RealTimeTwoActuators, BladeWithAtsOnEachActuatorTracksWithinOnePercent) {
  const fs::path dir = test_support::FreshTempDir("real_time_blade");
  const auto [status, output] = RunBlade(kExample, dir / "rt.csv", "virtual");
  ASSERT_EQ(status, 0) << output;
  const io::RunData run = io::LoadRun((dir / "rt.csv").string());
  const nlohmann::json rt = run.metadata["statistics"]["real_time"];
  ASSERT_EQ(rt["actuators"].size(), 2u) << rt.dump(1);
  for (const auto& a : rt["actuators"]) {
    EXPECT_EQ(a["substructure"], "blade1");
    EXPECT_LE(a["J2"].get<double>(), 1.0) << a.dump();
    EXPECT_TRUE(a["J1_ms"].is_number()) << a.dump();
    EXPECT_TRUE(a["J3"].is_number()) << a.dump();
  }
  ASSERT_EQ(rt["slots"].size(), 2u);
  EXPECT_EQ(rt["slots"][0]["slot"], "r_flap");
  EXPECT_EQ(rt["slots"][1]["slot"], "r_edge");
  // Each actuator's own compensator, and the coupled delay check of both slots together.
  EXPECT_EQ(rt["compensation"]["blade1"]["actuators"].size(), 2u) << rt["compensation"].dump();
  for (const auto& g : rt["stability"]) EXPECT_EQ(g["delayed_together"], 2) << g.dump();
  EXPECT_EQ(rt["misses"], 0);
}

// The example with its plant ideal (no delay, no lag) and no compensator, as a file next to
// nothing (the model's path made absolute), 2 s of it; `paced`: with or without its
// `real_time:` block.
fs::path IdealVariant(const fs::path& dir, bool paced) {
  YAML::Node config = YAML::LoadFile(kExample);
  config["model"]["file"] = kSource + "/examples/06_blade_two_actuators/blade_tip.yaml";
  config["duration"] = 2.0;  // [s] 2,048 ticks: the load ramp and a few millimetres
  YAML::Node sub = config["substructures"]["blade1"];
  YAML::Node plant = YAML::Clone(sub["transfer"]["inner"]);
  plant["plant"] = "ideal";
  sub["transfer"] = plant;
  if (paced) {
    config["real_time"]["clock"] = "virtual";
  } else {
    config.remove("real_time");
  }
  const fs::path path = dir / (paced ? "paced.yaml" : "settled.yaml");
  std::ofstream(path) << YAML::Dump(config) << "\n";
  return path;
}

TEST(RealTimeTwoActuators, IdealPlantEqualsThePseudoDynamicRun) {
  const fs::path dir = test_support::FreshTempDir("real_time_blade_ideal");
  const auto [s1, o1] = RunBlade(IdealVariant(dir, true).string(), dir / "paced.csv", "");
  ASSERT_EQ(s1, 0) << o1;
  const auto [s2, o2] = RunBlade(IdealVariant(dir, false).string(), dir / "settled.csv", "");
  ASSERT_EQ(s2, 0) << o2;
  const io::RunData paced = io::LoadRun((dir / "paced.csv").string());
  const io::RunData settled = io::LoadRun((dir / "settled.csv").string());
  ASSERT_TRUE(paced.metadata["statistics"].contains("real_time"));
  ASSERT_FALSE(settled.metadata["statistics"].contains("real_time"));
  ASSERT_EQ(paced.num_rows(), settled.num_rows());
  ASSERT_GT(paced.num_rows(), 2000);
  double worst = 0.0, peak = 0.0;
  for (const char* name : {"q_flap", "q_edge", "u1", "u2", "r_flap", "r_edge",
                           "blade1_a1_command", "blade1_a2_position"}) {
    const int a = paced.Column(name), b = settled.Column(name);
    ASSERT_GE(a, 0) << name;
    ASSERT_GE(b, 0) << name;
    for (long i = 0; i < paced.num_rows(); ++i) {
      const double x = paced.values(i, a), y = settled.values(i, b);
      if (name[0] == 'q') {
        worst = std::max(worst, std::abs(x - y));
        peak = std::max(peak, std::abs(y));
      }
      ASSERT_NEAR(x, y, name[0] == 'r' ? 1e-5 : 1e-9) << name << " row " << i;
    }
  }
  EXPECT_GT(peak, 1e-3);  // the blade moves by millimetres
  RecordProperty("largest_q_difference_m", fmt::format("{:.3g}", worst));
}

}  // namespace
}  // namespace hybridtest
