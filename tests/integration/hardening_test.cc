// Issue 10 end to end, with real processes: a remote run succeeds while another process holds
// an idle connection to the bench; every bad input exits 2 naming the key or argument; the
// token stays out of the command line and the results; a unit slip in the runner's limits and
// a step beyond the stability limit are refused before anything moves.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "integration/bench_process.h"
#include "integration/child_process.h"
#include "support/temp_dir.h"
#include "hybridtest/transfer/socket.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;
using testing::BenchProcess;
using testing::RunCommand;

const std::string kSource = HYBRIDTEST_SOURCE_DIR;
const std::string kExe = HYBRIDTEST_BINARY;
const std::string kIdealBench = kSource + "/examples/rotor/bench-ideal.yaml";

// One directory per test process, made on first use.
fs::path OutDir() {
  static const fs::path dir = test_support::FreshTempDir("hardening");
  return dir;
}

std::string Write(const std::string& name, const std::string& text) {
  const fs::path path = OutDir() / name;
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

// A short remote rotor run (heun, 1 ms, 10 steps) with the given safety and transfer extras.
std::string RemoteConfig(const std::string& safety, const std::string& transfer_extra = "") {
  return "model: {name: rotor, blades: 3}\n"
         "integrator: {tableau: heun, dt: 0.001}\n"
         "duration: 0.01\n"
         "substructures:\n"
         "  r1:\n"
         "    type: physical\n"
         "    transfer: {type: remote, address: 127.0.0.1:1, timeout: 5" + transfer_extra + "}\n"
         "    setup: {p0: 0.020}\n"
         "    safety: " + safety + "\n";
}
const std::string kSafety =
    "{stroke_min: -0.15, stroke_max: 0.15, max_increment: 0.005, force_soft: 8000, "
    "force_hard: 10000, timeout: 5}";

TEST(Hardening, RemoteExampleRunsWhileAnIdleConnectionIsOpen) {
  BenchProcess bench({"--config", kIdealBench});
  // Another "process" (a raw socket) connects first and says nothing.
  transfer::Socket idle = transfer::ConnectTcp("127.0.0.1", bench.port(), 5.0);
  const std::string csv = (OutDir() / "remote.csv").string();
  const auto [status, out] =
      RunCommand(kExe + " run " + kSource + "/examples/rotor/remote.yaml --quiet --bench 127.0.0.1:" +
                 std::to_string(bench.port()) + " --out " + csv,
                 600);  // a bound, not a timing: the run is 10,000 committed steps over TCP
  EXPECT_EQ(status, 0) << out;
  EXPECT_TRUE(fs::exists(csv));
}

TEST(Hardening, BadInputExitsTwoNamingTheKey) {
  const std::string rotor = "model: {name: rotor, blades: 3}\n";
  const std::string heun = "integrator: {tableau: heun, dt: 0.001}\n";
  const std::string physical =
      rotor + heun + "duration: 0.01\nsubstructures:\n  r1:\n    type: physical\n"
      "    transfer: {type: loopback, law: {type: linear, stiffness: 7200}}\n";
  const std::pair<std::string, std::string> cases[] = {
      {physical + "    safety: 5\n", "safety"},
      {physical + "    safety: [1, 2]\n", "safety"},
      {physical + "    safety: defaults\n    setup: 5\n", "setup"},
      {rotor + "integrator: {tableau: heun, dt: 1}\nduration: 1e19\n", "duration"},
      {"model: {name: rotor, blades: 1e9}\n" + heun + "duration: 1\n", "model.blades"},
      {rotor + heun + "duration: 0.01\n# caf\xE9\n", "UTF-8"},
      {rotor + heun + "duration: 0.01\nmodel2: {[1]: 2}\n", "model2"},
  };
  int i = 0;
  for (const auto& [text, key] : cases) {
    const std::string path = Write("bad" + std::to_string(i++) + ".yaml", text);
    for (const std::string command : {"simulate", "run"}) {
      // `simulate` refuses a physical slot first, whatever its keys say.
      if (command == "simulate" && text.find("physical") != std::string::npos) continue;
      const auto [status, out] = RunCommand(kExe + " " + command + " " + path + " --quiet");
      EXPECT_EQ(status, 2) << command << " " << text << "\n" << out;
      EXPECT_NE(out.find(key), std::string::npos) << out;
      EXPECT_EQ(out.find("internal error"), std::string::npos) << out;
    }
  }
  // A path that is not UTF-8.
  const std::string bad_path = Write("caf\xE9.yaml", rotor + heun + "duration: 0.01\n");
  auto [status, out] = RunCommand(kExe + " simulate '" + bad_path + "' --quiet");
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("UTF-8"), std::string::npos) << out;
}

TEST(Hardening, CommandLineErrorsExitTwo) {
  for (const std::string args : {"simulat", "report /no/such/run.csv", "run", "bench --bogus",
                                 "simulate --no-such-option x.yaml"}) {
    const auto [status, out] = RunCommand(kExe + " " + args);
    EXPECT_EQ(status, 2) << args << "\n" << out;
  }
  EXPECT_EQ(RunCommand(kExe + " --help").first, 0);
  EXPECT_EQ(RunCommand(kExe + " --version").first, 0);
}

// Numeric options refuse NaN, infinities, signs out of range and trailing text (they used to
// fall back to a default, or `inf` disabled a check), naming the option and the value.
TEST(Hardening, NumericOptionsAreValidatedNotReplaced) {
  // An existing regular file as the run: the option, not the path, is what is wrong.
  const std::string config = kSource + "/examples/rotor/numerical.yaml";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"resume " + config + " --force-tolerance nan", "--force-tolerance"},
      {"resume " + config + " --force-tolerance -5", "--force-tolerance"},
      {"resume " + config + " --force-tolerance 0", "--force-tolerance"},
      {"resume " + config + " --force-tolerance inf", "--force-tolerance"},
      {"resume " + config + " --position-tolerance 1mm", "--position-tolerance"},
      {"eom " + config + " --time nan --state 0,0,0,0,0,0,0,0", "--time"},
      {"plan " + config + " --tolerance -0.01", "--tolerance"},
      {"compare " + config + " " + config + " --transient inf", "--transient"},
  };
  for (const auto& [args, option] : cases) {
    const auto [status, out] = RunCommand(kExe + " " + args);
    EXPECT_EQ(status, 2) << args << "\n" << out;
    EXPECT_NE(out.find(option), std::string::npos) << args << "\n" << out;
  }
}

TEST(Hardening, ReportCreatesTheFoldersOfOut) {
  const std::string config = Write("tiny.yaml", "model: {name: rotor, blades: 3}\n"
                                                "integrator: {tableau: heun, dt: 0.001}\n"
                                                "duration: 0.01\n");
  const std::string csv = (OutDir() / "tiny.csv").string();
  ASSERT_EQ(RunCommand(kExe + " simulate " + config + " --quiet --out " + csv).first, 0);
  const fs::path html = OutDir() / "new" / "folder" / "x.html";
  const auto [status, out] = RunCommand(kExe + " report " + csv + " --out " + html.string());
  EXPECT_EQ(status, 0) << out;
  EXPECT_TRUE(fs::exists(html));
}

TEST(Hardening, StepBeyondTheStabilityLimitIsRefusedWithTheLargestStableStep) {
  const std::string rotor = "model: {name: rotor, blades: 3}\nduration: 0.1\n";
  const std::string too_big = Write("dt5.yaml", rotor + "integrator: {tableau: heun, dt: 0.005}\n");
  const auto [status, out] = RunCommand(kExe + " simulate " + too_big + " --quiet");
  EXPECT_EQ(status, 2) << out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, std::regex("largest stable step is ([0-9.]+) ms"))) << out;
  EXPECT_NEAR(std::stod(m[1].str()), 2.09, 0.01);  // heun on the paper's rotor
  EXPECT_NE(out.find("integrator.dt"), std::string::npos) << out;
  const std::string fine = Write("dt1.yaml", rotor + "integrator: {tableau: heun, dt: 0.001}\n");
  EXPECT_EQ(RunCommand(kExe + " simulate " + fine + " --quiet --out " +
                       (OutDir() / "dt1.csv").string()).first, 0);
}

TEST(Hardening, TokenComesFromAFileAndNeverReachesTheResults) {
  const std::string token = "t0ken-" + std::to_string(::getpid());
  const std::string token_file = Write("bench.token", token + "\n");
  // On the command line it is refused (it would show in /proc/PID/cmdline).
  const auto [refused, why] = RunCommand(kExe + " bench --listen 127.0.0.1:0 --token " + token);
  EXPECT_EQ(refused, 2) << why;
  EXPECT_NE(why.find("--token-file"), std::string::npos) << why;

  BenchProcess bench({"--config", kIdealBench, "--token-file", token_file});
  EXPECT_NE(bench.first_line().find("token required"), std::string::npos);
  const std::string bench_arg = " --quiet --bench 127.0.0.1:" + std::to_string(bench.port());
  // Without the token: refused by the bench (transfer error).
  const std::string without = Write("without.yaml", RemoteConfig(kSafety));
  EXPECT_EQ(RunCommand(kExe + " run " + without + bench_arg + " --out " +
                       (OutDir() / "without.csv").string()).first, 4);
  // With token_file: runs, and neither the journal nor the sidecar holds the token.
  const std::string with = Write("with.yaml", RemoteConfig(kSafety, ", token_file: bench.token"));
  const std::string csv = (OutDir() / "with.csv").string();
  const auto [status, out] = RunCommand(kExe + " run " + with + bench_arg + " --out " + csv);
  EXPECT_EQ(status, 0) << out;
  const std::string meta = ReadText(OutDir() / "with.meta.json");
  EXPECT_FALSE(meta.empty());
  EXPECT_EQ(meta.find(token), std::string::npos);
  EXPECT_EQ(ReadText(csv).find(token), std::string::npos);
  // Inline in the run config: refused before anything connects.
  const std::string inline_token =
      Write("inline.yaml", RemoteConfig(kSafety, ", token: " + token));
  const auto [inline_status, inline_out] = RunCommand(kExe + " run " + inline_token + bench_arg);
  EXPECT_EQ(inline_status, 2) << inline_out;
  EXPECT_NE(inline_out.find("token_file"), std::string::npos) << inline_out;
}

TEST(Hardening, RunnerLimitsInTheWrongUnitAreRefusedAtConnection) {
  BenchProcess bench({"--config", kIdealBench});
  const std::string config = Write(
      "mm.yaml", RemoteConfig("{stroke_min: -150, stroke_max: 150, max_increment: 0.005, "
                              "force_soft: 8000, force_hard: 10000, timeout: 5}"));
  const auto [status, out] =
      RunCommand(kExe + " run " + config + " --quiet --bench 127.0.0.1:" +
                 std::to_string(bench.port()) + " --out " + (OutDir() / "mm.csv").string());
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("substructures.r1.safety.stroke_min = -150 m"), std::string::npos) << out;
  EXPECT_NE(out.find("about 1000 times"), std::string::npos) << out;
}

}  // namespace
}  // namespace hybridtest
