// `hybridtest probe`, `run` and `resume` over ADS, against `hybridtest bench --protocol ads`
// in its own process (issue 50):
//   - the PLC side of docs/ads.md: probe, run, a hybridtest that hangs (SIGSTOP: its heartbeat
//     stops, the emulator's P_Hybrid watchdog sets the hold), then resume, which clears it;
//   - resume without --bench uses the bench the run recorded, and a resume that cannot reach
//     the PLC leaves the reason the run stopped as it was, its failure recorded beside it.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <fstream>
#include <sstream>
#include <thread>

#include "hybridtest/io/journal.h"
#include "integration/bench_process.h"
#include "integration/resume_support.h"

namespace hybridtest::testing {
namespace {

const std::string kIdeal = kSource + "/examples/rotor/bench-ideal.yaml";

// examples/rotor/ads.yaml with `duration` [s], in `dir`.
std::string ShortRotor(const fs::path& dir, const std::string& duration) {
  std::ifstream in(kSource + "/examples/rotor/ads.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  yaml.replace(yaml.find("duration: 10.0"), 14, "duration: " + duration);
  const fs::path config = dir / "rotor.yaml";
  std::ofstream(config) << yaml;
  return config.string();
}

std::string Probe(const std::string& config, const std::string& bench, const fs::path& log) {
  Child probe(HybridtestArgv({"probe", config, "--bench", bench}), log);
  probe.WaitExit(60.0);
  return probe.output();
}

TEST(AdsCommands, ProbeRunAHangTheWatchdogHoldsThenResumeWithTheRecordedBench) {
  const fs::path dir = ResumeTestDir("ads-p-hybrid");
  const std::string config = ShortRotor(dir, "0.05");
  const fs::path csv = dir / "run.csv";
  BenchProcess plc({"--protocol", "ads", "--config", kIdeal, "--plc-program", "p_hybrid",
                    "--watchdog", "0.5"});
  const std::string bench = fmt::format("127.0.0.1:{}", plc.port());
  const std::string probed = Probe(config, bench, dir / "probe.log");
  EXPECT_NE(probed.find("not enabled, not holding"), std::string::npos) << probed;

  Child run(HybridtestArgv(RunArgs(config, csv, bench)), dir / "run.log");
  for (int i = 0; i < 6000; ++i) {  // ≤ 60 s: until a few rows are committed
    if (fs::exists(csv) && ReadLines(csv).size() >= 5) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  run.Signal(SIGSTOP);  // hybridtest hangs, its connection open: no heartbeat
  bool held = false;
  for (int i = 0; i < 40 && !held; ++i) {
    held = Probe(config, bench, dir / "probe.log").find(", holding") != std::string::npos;
  }
  run.Signal(SIGKILL);
  EXPECT_EQ(run.WaitExit(60.0), 128 + SIGKILL);
  ASSERT_TRUE(held) << "the PLC's watchdog never held";

  const auto [status, output] = Resume(csv, {"--quiet"}, dir / "resume.log");
  EXPECT_EQ(status, 0) << output;
  EXPECT_NE(output.find("the bench the run recorded, --bench " + bench), std::string::npos) << output;
  EXPECT_EQ(io::ReadSidecar(csv.string()).value("status", ""), "completed");
  fs::remove_all(dir);
}

TEST(AdsCommands, AResumeThatCannotReachThePlcKeepsTheReasonTheRunStopped) {
  const fs::path dir = ResumeTestDir("ads-resume-down");
  const std::string config = ShortRotor(dir, "0.2");
  const fs::path csv = dir / "run.csv";
  std::string bench;
  {
    BenchProcess plc({"--protocol", "ads", "--config", kIdeal, "--inject", "holding@101"});
    bench = fmt::format("127.0.0.1:{}", plc.port());
    Child run(HybridtestArgv(RunArgs(config, csv, bench)), dir / "run.log");
    ASSERT_EQ(run.WaitExit(120.0), 4) << run.output();
  }  // the PLC is gone
  const std::string stopped = io::ReadSidecar(csv.string()).value("status", "");
  ASSERT_NE(stopped.find("reports holding"), std::string::npos) << stopped;

  // Without --bench: the run's bench (before: the config's port 48898), which is down.
  const auto [status, output] = Resume(csv, {"--quiet"}, dir / "resume.log");
  EXPECT_NE(status, 0) << output;
  EXPECT_NE(output.find("cannot connect to " + bench), std::string::npos) << output;
  const nlohmann::json sidecar = io::ReadSidecar(csv.string());
  EXPECT_EQ(sidecar.value("status", ""), stopped) << "a failed resume replaced the stop reason";
  ASSERT_TRUE(sidecar.contains("resumes") && !sidecar["resumes"].empty()) << sidecar.dump(1);
  const std::string attempt = sidecar["resumes"].back()["stopped"].value("status", "");
  EXPECT_NE(attempt.find("cannot connect to " + bench), std::string::npos) << attempt;

  // The PLC back on another port, named: the run completes.
  BenchProcess plc({"--protocol", "ads", "--config", kIdeal});
  const auto [again, again_output] =
      Resume(csv, {"--quiet", "--bench", fmt::format("127.0.0.1:{}", plc.port())},
             dir / "resume2.log");
  EXPECT_EQ(again, 0) << again_output;
  EXPECT_EQ(io::ReadSidecar(csv.string()).value("status", ""), "completed");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::testing
