// `hybridtest bench --protocol openfresco` serving the ideal two-actuator bench of
// examples/06_blade_two_actuators as a real process: the blade-tip model with both slots on the
// OpenFresco client (an element of two degrees of freedom, the run's setup the identity) must
// reproduce the simulation with the numerical substructure Tᵀ K T; and the server with a 2 × 4
// transform answers getForce with q = Tᵀ f and getTangentStiff with Tᵀ K T (column-major).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/session.h"
#include "integration/bench_process.h"
#include "transfer/openfresco/raw_peer.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;
const std::string kExample = std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/06_blade_two_actuators/";
const std::string kBinary = HYBRIDTEST_BINARY;

// Every committed row's [q; u].
class StateRecorder final : public runner::SessionObserver {
 public:
  void OnCommit(const runner::CommitEvent& e) override {
    if (e.kind == runner::RowKind::kCommitted) rows.emplace_back(e.x.begin(), e.x.end());
  }
  std::vector<std::vector<double>> rows;
};

// Runs `spec` in memory (no files) and returns its committed states.
std::vector<std::vector<double>> RunInMemory(io::RunSpec spec) {
  spec.output.files = false;
  spec.quiet = true;
  runner::Session session(std::move(spec));
  StateRecorder recorder;
  session.AddObserver(recorder);
  const runner::StepResult r = session.Run();
  EXPECT_EQ(r.status, runner::SessionStatus::kFinished) << r.reason;
  return recorder.rows;
}

// The contract through OpenFresco: Heun at 1 ms over 10 s, within 1e-9 (SI).
TEST(OpenFrescoTwoActuators, RunThroughTheClientMatchesTheNumericalSubstructure) {
  testing::BenchProcess bench(
      {"--protocol", "openfresco", "--config", kExample + "bench-2act-openfresco.yaml"});
  EXPECT_NE(bench.first_line().find("OpenFresco protocol, n = 2, 2 actuators"), std::string::npos)
      << bench.first_line();
  io::SubstructureOptions options;
  options.bench_address = fmt::format("127.0.0.1:{}", bench.port());
  const io::RunSpec hybrid = io::LoadRunSpec(kExample + "openfresco.yaml", options);
  ASSERT_EQ(hybrid.substructures.size(), 1u);
  ASSERT_EQ(hybrid.scheme.duration, 10.0);
  const auto through = RunInMemory(hybrid);
  const auto numerical = RunInMemory(io::LoadRunSpec(kExample + "dummy.yaml"));
  ASSERT_EQ(through.size(), 10001u);
  ASSERT_EQ(through.size(), numerical.size());
  double worst = 0.0, peak_flap = 0.0, peak_edge = 0.0;
  for (std::size_t i = 0; i < through.size(); ++i) {
    ASSERT_EQ(through[i].size(), 4u);  // q_flap, q_edge, u1, u2
    for (std::size_t j = 0; j < 4; ++j) {
      worst = std::max(worst, std::abs(through[i][j] - numerical[i][j]));
    }
    peak_flap = std::max(peak_flap, std::abs(numerical[i][0]));
    peak_edge = std::max(peak_edge, std::abs(numerical[i][1]));
  }
  std::printf("[ measured ] OpenFresco client (dofs 2) against the numerical Tᵀ K T: largest "
              "|Δq|, |Δu| over 10,001 rows = %.3g (SI)\n", worst);
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(peak_flap, 1e-3);  // both deflections move by millimetres
  EXPECT_GT(peak_edge, 1e-3);
  bench.Signal(SIGTERM);
  EXPECT_EQ(bench.WaitExit(10.0), 0);
}

// The same run from the command line, shortened: the journal has one channel group per degree
// of freedom; a `dofs` that does not match the slots is refused before anything connects.
TEST(OpenFrescoTwoActuators, CommandLineRunAndDofsMismatch) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("hybridtest_of2_{}", getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ostringstream text;
  text << std::ifstream(kExample + "openfresco.yaml").rdbuf();
  std::string config = text.str();
  auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = config.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    config.replace(at, from.size(), to);
  };
  replace("file: blade_tip.yaml", "file: " + kExample + "blade_tip.yaml");
  replace("duration: 10.0", "duration: 0.2");
  std::ofstream(dir / "run.yaml") << config;
  testing::BenchProcess bench(
      {"--protocol", "openfresco", "--config", kExample + "bench-2act-openfresco.yaml"});
  auto [status, out] = testing::RunCommand(fmt::format(
      "{} run {} --bench 127.0.0.1:{} --out {} --quiet", kBinary, (dir / "run.yaml").string(),
      bench.port(), (dir / "run.csv").string()));
  ASSERT_EQ(status, 0) << out;
  std::ifstream csv(dir / "run.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_NE(header.find("blade1_a2_force"), std::string::npos) << header;

  replace("dofs: 2 ", "dofs: 3 ");
  std::ofstream(dir / "bad.yaml") << config;
  std::tie(status, out) = testing::RunCommand(fmt::format(
      "{} run {} --bench 127.0.0.1:{} --out {} --quiet", kBinary, (dir / "bad.yaml").string(),
      bench.port(), (dir / "bad.csv").string()));
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("substructures.blade1.transfer.dofs"), std::string::npos) << out;
  EXPECT_NE(out.find("drives 2 actuators"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "bad.csv"));
  bench.Signal(SIGTERM);
  EXPECT_EQ(bench.WaitExit(10.0), 0);
  fs::remove_all(dir);
}

// The contract for the server, through the command line: a 2 × 4 transform on the
// two-actuator bench; action 10 answers q = Tᵀ f, action 13 Tᵀ K T (column-major). The
// reported K is the section's `initial_stiffness`, given unsymmetric here so that the order of
// the 16 words is seen (a symmetric Tᵀ K T reads the same in either order).
TEST(OpenFrescoTwoActuators, ServerWithATwoByFourTransform) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("hybridtest_of24_{}", getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  {
    std::ifstream ideal(kExample + "bench-2act.yaml");
    std::ofstream out(dir / "bench.yaml");
    out << ideal.rdbuf()
        << "openfresco: {units: {length: mm, force: N}, "
           "transform: [[0.6, -0.8, -0.6, 0.8], [0.0, 1.0, 0.0, -1.0]], "
           "initial_stiffness: [[5000, 1200], [800, 3000]]}\n";
  }
  testing::BenchProcess bench({"--protocol", "openfresco", "--config", (dir / "bench.yaml").string()});
  EXPECT_NE(bench.first_line().find("n = 4, 2 actuators"), std::string::npos) << bench.first_line();
  const double T[2][4] = {{0.6, -0.8, -0.6, 0.8}, {0.0, 1.0, 0.0, -1.0}};
  const double K[2][2] = {{5.0, 1.2}, {1.2, 3.0}};   // [N/mm]: bench-2act.yaml's specimen
  const double K0[2][2] = {{5.0, 1.2}, {0.8, 3.0}};  // [N/mm]: initial_stiffness
  testing::RawPeer peer(bench.port());
  ASSERT_TRUE(peer.SendInts({4, 4, 4, 0, 1, 0, 0, 0, 4, 0, 256}));  // OpenSees's header
  const double d[4] = {0.5, 1.0, -0.25, -0.5};                     // [mm]
  ASSERT_TRUE(peer.SendDoubles({3, d[0], d[1], d[2], d[3], 0, 0, 0, 0, 0, 0, 0, 0, 0}, 256));
  double f[2] = {0.0, 0.0};  // K (T d) [N]
  for (int a = 0; a < 2; ++a) {
    for (int b = 0; b < 2; ++b) {
      for (int i = 0; i < 4; ++i) f[a] += K[a][b] * T[b][i] * d[i];
    }
  }
  ASSERT_TRUE(peer.SendDoubles({10}, 256));
  const auto q = peer.ReadDoubles(256);
  ASSERT_TRUE(q) << "no reply to action 10";
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR((*q)[i], T[0][i] * f[0] + T[1][i] * f[1], 1e-9) << "q[" << i << "] [N]";
  }
  ASSERT_TRUE(peer.SendDoubles({13}, 256));
  const auto kd = peer.ReadDoubles(256);
  ASSERT_TRUE(kd) << "no reply to action 13";
  for (int col = 0; col < 4; ++col) {
    for (int row = 0; row < 4; ++row) {
      double expected = 0.0;
      for (int a = 0; a < 2; ++a) {
        for (int b = 0; b < 2; ++b) expected += T[a][row] * K0[a][b] * T[b][col];
      }
      EXPECT_NEAR((*kd)[4 * col + row], expected, 1e-12) << "K(" << row << "," << col << ")";
    }
  }
  ASSERT_TRUE(peer.SendDoubles({99}, 256));
  EXPECT_TRUE(peer.ClosedByPeer());
  bench.Signal(SIGTERM);
  EXPECT_EQ(bench.WaitExit(10.0), 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest
