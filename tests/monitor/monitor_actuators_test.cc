// Every actuator in view (issue 38): on the two-actuator blade of
// examples/06_blade_two_actuators/bouc-wen.yaml (0.2 s of it), /api/state has one meter group
// per actuator (name, substructure, its slots, its own p0 and limits, as the config gives them)
// whose command, position and force are the journal's last row for that actuator; the series
// has every actuator's columns and every model slot's; and a follower of the run's journal
// (`hybridtest monitor RUN.csv`) shows the same actuators, limits and p0, the last row's
// values, and the elapsed time, lab time and evaluations the sidecar records.
#include <gtest/gtest.h>

#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/monitor/monitor_observer.h"
#include "hybridtest/monitor/run_follower.h"
#include "monitor/example_config.h"

namespace hybridtest::testing {
namespace {

// bouc-wen.yaml, 0.2 s of it.
fs::path WriteBladeConfig(const fs::path& dir) {
  return WriteExampleConfig(dir, "06_blade_two_actuators", "bouc-wen.yaml",
                            {{"duration: 10.0", "duration: 0.2"}},
                            {"blade_tip.yaml", "bench-2act-bouc-wen.yaml"});
}

class Rows final : public runner::SessionObserver {
 public:
  void OnCommit(const runner::CommitEvent& e) override {
    if (e.kind == runner::RowKind::kCommitted) last.assign(e.row.begin(), e.row.end());
  }
  std::vector<double> last;
};

// The meters of the blade's two actuators, as bouc-wen.yaml configures them.
void ExpectBladeActuators(const nlohmann::json& actuators) {
  ASSERT_EQ(actuators.size(), 2u) << actuators.dump();
  const double p0[] = {0.02, 0.03};
  for (int k = 0; k < 2; ++k) {
    const nlohmann::json& a = actuators[std::size_t(k)];
    EXPECT_EQ(a["name"], "blade1_a" + std::to_string(k + 1));
    EXPECT_EQ(a["substructure"], "blade1");
    EXPECT_EQ(a["index"], k);
    EXPECT_EQ(a["slots"], (nlohmann::json{"r_flap", "r_edge"}));
    ASSERT_TRUE(a["p0"].is_number()) << a.dump();
    EXPECT_DOUBLE_EQ(a["p0"].get<double>(), p0[k]);
    ASSERT_TRUE(a["limits"].is_object()) << a.dump();
    EXPECT_DOUBLE_EQ(a["limits"]["stroke_min"].get<double>(), -0.10);
    EXPECT_DOUBLE_EQ(a["limits"]["stroke_max"].get<double>(), 0.10);
    EXPECT_DOUBLE_EQ(a["limits"]["max_increment"].get<double>(), 0.002);
    EXPECT_DOUBLE_EQ(a["limits"]["force_soft"].get<double>(), 2000.0);
    EXPECT_DOUBLE_EQ(a["limits"]["force_hard"].get<double>(), 3000.0);
    EXPECT_DOUBLE_EQ(a["displacement"].get<double>(), a["position"].get<double>() - p0[k]);
    EXPECT_TRUE(a["margin"].is_object());
  }
}

TEST(MonitorActuators, EveryActuatorOfTheBladeHasItsOwnMetersFromTheSlotMap) {
  const fs::path dir = ResumeTestDir("monitor_actuators_live");
  io::RunSpec spec = io::LoadRunSpec(WriteBladeConfig(dir).string());
  spec.output.files = false;
  monitor::MonitorState state(100000);
  monitor::MonitorObserver observer(state);
  Rows rows;
  runner::Session session(std::move(spec));
  session.AddObserver(observer);
  session.AddObserver(rows);
  ASSERT_EQ(session.Run().status, runner::SessionStatus::kFinished);
  const nlohmann::json j = state.StateJson();
  ExpectBladeActuators(j["actuators"]);
  // The model's slots, by name, with r of the last row.
  ASSERT_EQ(j["slots"].size(), 2u);
  EXPECT_EQ(j["slots"][0]["name"], "r_flap");
  EXPECT_EQ(j["slots"][1]["name"], "r_edge");
  // The journal row: t, q (2), u (2), r (2), then per actuator command, position, force, lab.
  const std::vector<double>& row = rows.last;
  ASSERT_EQ(row.size(), 1u + 4 + 2 + 8);
  EXPECT_DOUBLE_EQ(j["slots"][0]["r"].get<double>(), row[5]);
  EXPECT_DOUBLE_EQ(j["slots"][1]["r"].get<double>(), row[6]);
  for (std::size_t k = 0; k < 2; ++k) {
    const nlohmann::json& a = j["actuators"][k];
    EXPECT_DOUBLE_EQ(a["command"].get<double>(), row[7 + 4 * k]);
    EXPECT_DOUBLE_EQ(a["position"].get<double>(), row[8 + 4 * k]);
    EXPECT_DOUBLE_EQ(a["force"].get<double>(), row[9 + 4 * k]);
  }
  // The two actuators are not the same channel twice.
  EXPECT_NE(row[9], row[13]);
  EXPECT_EQ(j["identity"]["bench"], "blade1: emulated (2 actuators)");
  const nlohmann::json series = state.SeriesJson(-1, -1);
  EXPECT_EQ(series["slots"], 2);
  EXPECT_EQ(series["actuators"], 2);
  EXPECT_DOUBLE_EQ(series["columns"]["force1"].back().get<double>(), row[13]);
  EXPECT_DOUBLE_EQ(series["columns"]["r1"].back().get<double>(), row[6]);
  fs::remove_all(dir);
}

TEST(MonitorActuators, AFollowerShowsEveryActuatorAndTheTimesTheSidecarRecords) {
  const fs::path dir = ResumeTestDir("monitor_actuators_follow");
  const fs::path csv = dir / "blade.csv";
  ASSERT_EQ(RunToEnd({"run", WriteBladeConfig(dir).string(), "--out", csv.string(), "--quiet"},
                     dir / "run.log"), 0);
  monitor::MonitorState state(100000);
  monitor::RunFollower follower(csv.string(), state);
  EXPECT_FALSE(follower.Poll());  // a finished run: nothing more to come
  const nlohmann::json j = state.StateJson();
  EXPECT_EQ(j["status"], "finished");
  EXPECT_EQ(j["identity"]["mode"], "follow");
  ExpectBladeActuators(j["actuators"]);
  // The last row's values, per actuator.
  const std::vector<std::string> lines = ReadLines(csv);
  const std::vector<std::string> header = SplitCsv(lines.front());
  const std::vector<std::string> last = SplitCsv(lines.back());
  auto value = [&](const std::string& channel) {
    const auto it = std::find(header.begin(), header.end(), channel);
    EXPECT_NE(it, header.end()) << channel;
    return std::stod(last[std::size_t(it - header.begin())]);
  };
  for (int k = 0; k < 2; ++k) {
    const std::string prefix = "blade1_a" + std::to_string(k + 1);
    const nlohmann::json& a = j["actuators"][std::size_t(k)];
    EXPECT_DOUBLE_EQ(a["command"].get<double>(), value(prefix + "_command"));
    EXPECT_DOUBLE_EQ(a["position"].get<double>(), value(prefix + "_position"));
    EXPECT_DOUBLE_EQ(a["force"].get<double>(), value(prefix + "_force"));
  }
  EXPECT_DOUBLE_EQ(j["slots"][1]["r"].get<double>(), value("r_edge"));
  // Elapsed, lab time and evaluations as recorded, not the follower's own clock.
  const nlohmann::json stats = Sidecar(csv)["statistics"];
  EXPECT_GT(stats["lab_time_s"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(j["wall_time"].get<double>(), stats["wall_time_s"].get<double>());
  EXPECT_DOUBLE_EQ(j["lab_time"].get<double>(), stats["lab_time_s"].get<double>());
  EXPECT_EQ(j["physical_evaluations"].get<long>(), stats["physical_evaluations"].get<long>());
  EXPECT_FALSE(j["realtime"]["available"].get<bool>());
  EXPECT_FALSE(j["realtime"]["paced"].get<bool>());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::testing
