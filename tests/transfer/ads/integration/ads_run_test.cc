// The `ads` transfer end to end against `hybridtest bench --protocol ads` (the TwinCAT PLC
// emulator in its own process):
//   - the contract: the paper's test over ADS on the ideal bench (examples/rotor/ads.yaml)
//     equals the numerical run (examples/rotor/numerical.yaml) within 1e-9 over 10 s (20,001
//     exchanges), and the two-actuator blade tip (examples/07_ads/blade-2act.yaml) equals its
//     numerical twin (examples/06_blade_two_actuators/dummy.yaml) within 1e-9, SI;
//   - a fault bit, an ADS error and a dropped connection mid-run each stop `hybridtest run`
//     with exit status 4, the reason named, and every committed row on disk.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "hybridtest/io/run_reader.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/session.h"
#include "integration/bench_process.h"
#include "integration/resume_support.h"

namespace hybridtest::testing {
namespace {

const std::string kAds = kSource + "/examples/07_ads/";
const std::string kIdeal = kSource + "/examples/rotor/bench-ideal.yaml";
const std::string kTwoActuators = kSource + "/examples/06_blade_two_actuators/";

// [q; u] of every committed row of an in-memory run of `config` (against `bench`, if given).
std::vector<std::vector<double>> CommittedStates(const std::string& config,
                                                 const std::string& bench = "") {
  struct Rows final : runner::SessionObserver {
    void OnCommit(const runner::CommitEvent& e) override {
      if (e.kind == runner::RowKind::kCommitted) x.emplace_back(e.x.begin(), e.x.end());
    }
    std::vector<std::vector<double>> x;
  } rows;
  io::SubstructureOptions options;
  if (!bench.empty()) options.bench_address = bench;
  io::RunSpec spec = io::LoadRunSpec(config, options);
  spec.output.files = false;
  spec.quiet = true;
  runner::Session session(std::move(spec));
  session.AddObserver(rows);
  const runner::StepResult r = session.Run();
  EXPECT_EQ(r.status, runner::SessionStatus::kFinished) << r.reason;
  return rows.x;
}

// The largest |difference| of two runs' states, after checking they have the same shape.
double LargestDifference(const std::vector<std::vector<double>>& a,
                         const std::vector<std::vector<double>>& b) {
  EXPECT_EQ(a.size(), b.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    EXPECT_EQ(a[i].size(), b[i].size());
    for (std::size_t j = 0; j < std::min(a[i].size(), b[i].size()); ++j) {
      worst = std::max(worst, std::abs(a[i][j] - b[i][j]));
    }
  }
  return worst;
}

TEST(AdsRun, ContractOneActuatorOverAdsEqualsTheNumericalRunWithin1e9) {
  BenchProcess plc({"--protocol", "ads", "--config", kIdeal});
  const auto ads = CommittedStates(kSource + "/examples/rotor/ads.yaml",
                                   fmt::format("127.0.0.1:{}", plc.port()));
  const auto numerical = CommittedStates(kSource + "/examples/rotor/numerical.yaml");
  ASSERT_EQ(ads.size(), 10001u);  // 10 s at 1 ms: 20,001 exchanges with Heun
  const double worst = LargestDifference(ads, numerical);
  std::cout << "[ one actuator over ADS: largest |Δx| against numerical.yaml " << worst << " ]\n";
  EXPECT_LT(worst, 1e-9);
  double peak = 0.0;
  for (const auto& x : numerical) peak = std::max(peak, std::abs(x[1]));
  EXPECT_GT(peak, 1e-3) << "too little motion to test anything";
}

TEST(AdsRun, ContractTwoActuatorsOverAdsEqualTheirNumericalTwinWithin1e9) {
  BenchProcess plc({"--protocol", "ads", "--config", kTwoActuators + "bench-2act.yaml"});
  const auto ads = CommittedStates(kAds + "blade-2act.yaml", fmt::format("127.0.0.1:{}", plc.port()));
  const auto numerical = CommittedStates(kTwoActuators + "dummy.yaml");
  ASSERT_EQ(ads.size(), 10001u);
  const double worst = LargestDifference(ads, numerical);
  std::cout << "[ two actuators over ADS: largest |Δx| against dummy.yaml " << worst << " ]\n";
  EXPECT_LT(worst, 1e-9);
}

// `hybridtest run` of rotor.yaml shortened to 0.2 s against the emulator with `fault`.
struct StoppedRun {
  int status = 0;
  std::string output;
  long rows = 0;
  std::string sidecar_status;
};
StoppedRun RunWithFault(const std::string& fault, const std::string& name) {
  const fs::path dir = ResumeTestDir("ads-" + name);
  std::ifstream in(kSource + "/examples/rotor/ads.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  yaml.replace(yaml.find("duration: 10.0"), 14, "duration: 0.2");
  const fs::path config = dir / "rotor.yaml";
  std::ofstream(config) << yaml;
  BenchProcess plc({"--protocol", "ads", "--config", kIdeal, "--inject", fault});
  const fs::path csv = dir / "run.csv";
  Child child(HybridtestArgv(RunArgs(config.string(), csv, fmt::format("127.0.0.1:{}", plc.port()))),
              dir / "run.log");
  StoppedRun r;
  r.status = child.WaitExit(120.0);
  r.output = child.output();
  const io::RunData data = io::LoadRun(csv.string());
  r.rows = data.num_rows();
  r.sidecar_status = data.metadata.at("status").get<std::string>();
  fs::remove_all(dir);
  return r;
}

TEST(AdsRun, AFaultBitMidRunStopsWithExit4AndEveryCommittedRow) {
  const StoppedRun r = RunWithFault("fault@101", "fault");
  EXPECT_EQ(r.status, 4) << r.output;
  EXPECT_NE(r.output.find("reports a fault (GVL_Hybrid.bFault = TRUE)"), std::string::npos) << r.output;
  // Heun's step from t = 0.050 s carries command 101 (the initial evaluation is command 1):
  // the 50 steps before it and the initial row are committed.
  EXPECT_EQ(r.rows, 51);
  EXPECT_EQ(r.sidecar_status.rfind("stopped", 0), 0u) << r.sidecar_status;
}

TEST(AdsRun, AnAdsErrorMidRunStopsWithExit4AndEveryCommittedRow) {
  const StoppedRun r = RunWithFault("ads_error@101", "error");
  EXPECT_EQ(r.status, 4) << r.output;
  EXPECT_NE(r.output.find("ADS error 0x708 (device busy)"), std::string::npos) << r.output;
  EXPECT_EQ(r.rows, 51);
}

TEST(AdsRun, ADroppedConnectionMidRunStopsWithExit4AndEveryCommittedRow) {
  const StoppedRun r = RunWithFault("close@101", "close");
  EXPECT_EQ(r.status, 4) << r.output;
  EXPECT_NE(r.output.find("the connection was lost"), std::string::npos) << r.output;
  EXPECT_EQ(r.rows, 51);
}

}  // namespace
}  // namespace hybridtest::testing
