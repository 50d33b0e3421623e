// `hybridtest bench --protocol openfresco` as a real process on 127.0.0.1: the issue's
// contract with a client written here (raw socket, hand-packed int32 and float64 words), and
// a `hybridtest run` that drives the bench through the OpenFresco client transfer
// (`transfer: {type: openfresco}`) and must reproduce the numerical simulation.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "hybridtest/io/run_reader.h"
#include "integration/bench_process.h"
#include "support/temp_dir.h"
#include "transfer/openfresco/raw_peer.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;
const std::string kSource = HYBRIDTEST_SOURCE_DIR;
const std::string kBinary = HYBRIDTEST_BINARY;

// The contract of issue 12, exactly as written.
TEST(OpenFrescoBenchProcess, Contract) {
  testing::BenchProcess bench(
      {"--protocol", "openfresco", "--config", kSource + "/examples/rotor/bench-openfresco.yaml"});
  EXPECT_NE(bench.first_line().find("OpenFresco protocol, n = 4"), std::string::npos)
      << bench.first_line();
  testing::RawPeer peer(bench.port());
  ASSERT_TRUE(peer.SendInts({4, 4, 4, 0, 0, 0, 0, 0, 4, 0, 256}));
  const std::vector<double> T{0.6, -0.8, -0.6, 0.8};
  const std::vector<double> d{0.0, 0.0, 1.06017, -0.355778};  // [mm]
  std::vector<double> trial{3.0};
  trial.insert(trial.end(), d.begin(), d.end());
  trial.resize(1 + 3 * 4, 0.0);  // v = a = 0
  ASSERT_TRUE(peer.SendDoubles(trial, 256));

  ASSERT_TRUE(peer.SendDoubles({13.0}, 256));  // getTangentStiff
  const auto K = peer.ReadDoubles(256);
  ASSERT_TRUE(K) << "no reply to action 13";
  for (int col = 0; col < 4; ++col) {
    for (int row = 0; row < 4; ++row) {
      EXPECT_NEAR((*K)[4 * col + row], T[row] * 7.2 * T[col], 1e-12)
          << "K(" << row << "," << col << ") [N/mm], column-major";
    }
  }

  ASSERT_TRUE(peer.SendDoubles({10.0}, 256));  // getForce
  const auto q = peer.ReadDoubles(256);
  ASSERT_TRUE(q) << "no reply to action 10";
  const double f = 7.2 * (T[0] * d[0] + T[1] * d[1] + T[2] * d[2] + T[3] * d[3]);  // [N]
  EXPECT_NEAR(f, -6.62921568, 1e-9);  // by hand: 7.2 × (−0.9207244)
  for (int i = 0; i < 4; ++i) EXPECT_NEAR((*q)[i], T[i] * f, 1e-6) << "q[" << i << "] [N]";

  ASSERT_TRUE(peer.SendDoubles({99.0}, 256));  // DIE: ends the session cleanly
  EXPECT_TRUE(peer.ClosedByPeer());
  // The server is still up and serves the next client.
  testing::RawPeer next(bench.port());
  ASSERT_TRUE(next.SendInts({4, 4, 4, 0, 1, 0, 0, 0, 4, 0, 256}));  // OpenSees's variant
  ASSERT_TRUE(next.SendDoubles({12.0}, 256));
  const auto K0 = next.ReadDoubles(256);
  ASSERT_TRUE(K0);
  EXPECT_NEAR((*K0)[0], 0.36 * 7.2, 1e-12);
  ASSERT_TRUE(next.SendDoubles({99.0}, 256));
  EXPECT_TRUE(next.ClosedByPeer());
  bench.Signal(SIGTERM);
  EXPECT_EQ(bench.WaitExit(10.0), 0);
}

TEST(OpenFrescoBenchProcess, MalformedHeaderNeverCrashesTheServer) {
  testing::BenchProcess bench(
      {"--protocol", "openfresco", "--config", kSource + "/examples/rotor/bench-openfresco.yaml"});
  {
    testing::RawPeer peer(bench.port());
    ASSERT_TRUE(peer.SendInts({-4, 99999, 4, 0, 0, 0, 0, 0, 4, 0, -1}));
    EXPECT_TRUE(peer.ClosedByPeer());
  }
  {
    testing::RawPeer peer(bench.port());
    ASSERT_TRUE(peer.SendInts({4, 4, 4, 0, 0, 0, 0, 0, 4, 0, 256}));
    ASSERT_TRUE(peer.SendDoubles({77.0}, 256));  // unknown action
    EXPECT_TRUE(peer.ClosedByPeer());
  }
  testing::RawPeer peer(bench.port());
  ASSERT_TRUE(peer.SendInts({4, 4, 4, 0, 0, 0, 0, 0, 4, 0, 256}));
  ASSERT_TRUE(peer.SendDoubles({15.0}, 256));
  EXPECT_TRUE(peer.ReadDoubles(256));
}

TEST(OpenFrescoBenchProcess, ArgumentErrorsAreClear) {
  auto [status, out] =
      testing::RunCommand(kBinary + " bench --protocol openfresco --listen 127.0.0.1:0");
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("needs --config"), std::string::npos) << out;
  std::tie(status, out) = testing::RunCommand(
      kBinary + " bench --protocol openfresco --listen 127.0.0.1:0 --config " + kSource +
      "/examples/rotor/bench-ideal.yaml");
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("no 'openfresco:' section"), std::string::npos) << out;
  std::tie(status, out) = testing::RunCommand(kBinary + " bench --protocol corba");
  EXPECT_NE(status, 0) << out;
}

// A hybrid test through the OpenFresco client: the rotor with blade r1 on the ideal bench
// (T = [[1]], mm and N on the wire) must match the numerical simulation within 1e-9 m.
TEST(OpenFrescoBenchProcess, RunThroughTheOpenFrescoClientMatchesTheSimulation) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("hybridtest_of_run_{}", getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  {
    std::ifstream ideal(kSource + "/examples/rotor/bench-ideal.yaml");
    std::ofstream out(dir / "bench.yaml");
    out << ideal.rdbuf() << "openfresco: {units: {length: mm, force: N}, transform: [[1]]}\n";
  }
  const std::string common =
      "model: {name: rotor, blades: 3}\nintegrator: {tableau: heun, dt: 0.001}\nduration: 0.5\n";
  std::ofstream(dir / "numerical.yaml") << common;
  std::ofstream(dir / "hybrid.yaml")
      << common
      << "substructures:\n  r1:\n    type: physical\n"
         "    transfer: {type: openfresco, host: 127.0.0.1, port: 1, timeout: 5}\n"
         "    setup: {p0: 0}   # the bench adds its own p0 = 20 mm\n"
         "    safety: {stroke_min: -0.15, stroke_max: 0.15, max_increment: 0.005, "
         "force_soft: 8000, force_hard: 10000, timeout: 5}\n";
  testing::BenchProcess bench(
      {"--protocol", "openfresco", "--config", (dir / "bench.yaml").string()});
  auto [status, out] = testing::RunCommand(fmt::format(
      "{} simulate {} --out {} --quiet", kBinary, (dir / "numerical.yaml").string(),
      (dir / "numerical.csv").string()));
  ASSERT_EQ(status, 0) << out;
  std::tie(status, out) = testing::RunCommand(fmt::format(
      "{} run {} --bench 127.0.0.1:{} --out {} --quiet", kBinary, (dir / "hybrid.yaml").string(),
      bench.port(), (dir / "hybrid.csv").string()));
  ASSERT_EQ(status, 0) << out;
  const io::RunData reference = io::LoadRun((dir / "numerical.csv").string());
  const io::RunData run = io::LoadRun((dir / "hybrid.csv").string());
  ASSERT_EQ(run.num_rows(), reference.num_rows());
  double worst = 0.0;
  for (const char* name : {"q1", "q2", "q3", "q4", "u1", "u2", "u3", "u4"}) {
    worst = std::max(worst, (run.Get(name) - reference.Get(name)).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-9) << "the OpenFresco path changed the result by " << worst;
  EXPECT_GT(run.Get("q1").cwiseAbs().maxCoeff(), 1e-3) << "too little motion to test anything";
  fs::remove_all(dir);
}

// ---- Issue 15 ----

// The hybrid run of the test above, in `dir`: bench.yaml (the ideal bench with an
// `openfresco:` setup) and hybrid.yaml whose transfer mapping is `transfer`.
void WriteHybridRun(const fs::path& dir, const std::string& transfer) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  {
    std::ifstream ideal(kSource + "/examples/rotor/bench-ideal.yaml");
    std::ofstream out(dir / "bench.yaml");
    out << ideal.rdbuf() << "openfresco: {units: {length: mm, force: N}, transform: [[1]]}\n";
  }
  std::ofstream(dir / "hybrid.yaml")
      << "model: {name: rotor, blades: 3}\nintegrator: {tableau: heun, dt: 0.001}\n"
         "duration: 0.2\nsubstructures:\n  r1:\n    type: physical\n"
         "    transfer: " << transfer << "\n"
         "    setup: {p0: 0}\n"
         "    safety: {stroke_min: -0.15, stroke_max: 0.15, max_increment: 0.005, "
         "force_soft: 8000, force_hard: 10000, timeout: 5}\n";
}

// The contract: `hybridtest bench --protocol openfresco` with one idle client connected serves
// another client's session at once. Before, the server sat in a blocking read on the idle
// socket for --heartbeat-timeout (here 60 s): the real client's 20 s read and the run's 5 s
// reply timeout would both have run out. The idle socket stays open on our side throughout.
TEST(OpenFrescoBenchProcess, IdleClientDoesNotHoldTheServer) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("hybridtest_of_idle_{}", getpid());
  WriteHybridRun(dir, "{type: openfresco, host: 127.0.0.1, port: 1, timeout: 5}");
  testing::BenchProcess bench({"--protocol", "openfresco", "--config",
                               (dir / "bench.yaml").string(), "--heartbeat-timeout", "60"});
  const auto start = std::chrono::steady_clock::now();
  testing::RawPeer idle(bench.port());  // connects and says nothing
  testing::RawPeer peer(bench.port());
  ASSERT_TRUE(peer.SendInts({1, 1, 1, 0, 1, 0, 0, 0, 1, 0, 256}));
  ASSERT_TRUE(peer.SendDoubles({3.0, 2.0}, 256));  // trial: 2 mm
  ASSERT_TRUE(peer.SendDoubles({10.0}, 256));      // getForce
  const auto q = peer.ReadDoubles(256, 20.0);
  ASSERT_TRUE(q) << "no reply while an idle client is connected";
  EXPECT_NEAR((*q)[0], 7.2 * 2.0, 1e-6);  // the ideal bench: 7.2 N/mm
  ASSERT_TRUE(peer.SendDoubles({99.0}, 256));
  EXPECT_TRUE(peer.ClosedByPeer());
  const double session_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // A whole hybrid run while another idle connection is open.
  testing::RawPeer idle_again(bench.port());
  auto [status, out] = testing::RunCommand(fmt::format(
      "{} run {} --bench 127.0.0.1:{} --out {} --quiet", kBinary, (dir / "hybrid.yaml").string(),
      bench.port(), (dir / "hybrid.csv").string()));
  EXPECT_EQ(status, 0) << out;
  const double total_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("[ measured ] session with an idle client connected: %.1f ms; with the run: %.3f s "
              "(heartbeat timeout 60 s)\n", 1e3 * session_s, total_s);
  bench.Signal(SIGTERM);
  EXPECT_EQ(bench.WaitExit(10.0), 0);
  fs::remove_all(dir);
}

// Issue 15: an inline `transfer.token` ended up in the sidecars, report.html and HDF5 export.
TEST(OpenFrescoBenchProcess, TokenNeverInTheConfigNorInAnyOutput) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("hybridtest_of_tok_{}", getpid());
  const std::string token = "tok-9f3c2a7e51d04b8c";
  WriteHybridRun(dir, "{type: openfresco, host: 127.0.0.1, port: 1, timeout: 5, token: " +
                          token + "}");
  auto [status, out] = testing::RunCommand(fmt::format(
      "{} run {} --out {} --quiet", kBinary, (dir / "hybrid.yaml").string(),
      (dir / "refused.csv").string()));
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("substructures.r1.transfer.token"), std::string::npos) << out;
  EXPECT_NE(out.find("token_file"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "refused.csv"));

  // The same run with `token_file:` against a bench that requires the token.
  WriteHybridRun(dir, "{type: openfresco, host: 127.0.0.1, port: 1, timeout: 5, "
                      "token_file: bench.token}");
  std::ofstream(dir / "bench.token") << token << "\n";
  fs::create_directories(dir / "out");
  testing::BenchProcess bench({"--protocol", "openfresco", "--config",
                               (dir / "bench.yaml").string(), "--token-file",
                               (dir / "bench.token").string()});
  EXPECT_NE(bench.first_line().find("token required"), std::string::npos) << bench.first_line();
  std::tie(status, out) = testing::RunCommand(fmt::format(
      "{} run {} --bench 127.0.0.1:{} --out {} --quiet", kBinary, (dir / "hybrid.yaml").string(),
      bench.port(), (dir / "out" / "hybrid.csv").string()));
  ASSERT_EQ(status, 0) << out;
  EXPECT_EQ(out.find(token), std::string::npos) << out;
  const std::string csv = (dir / "out" / "hybrid.csv").string();
  std::tie(status, out) = testing::RunCommand(fmt::format(
      "{} report {} --out {}", kBinary, csv, (dir / "out" / "report.html").string()));
  EXPECT_EQ(status, 0) << out;
  std::tie(status, out) = testing::RunCommand(fmt::format(
      "{} export {} --hdf5 {}", kBinary, csv, (dir / "out" / "run.h5").string()));
  EXPECT_EQ(status, 0) << out;
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir / "out")) {
    if (!entry.is_regular_file()) continue;
    ++files;
    const std::string content = test_support::ReadText(entry.path());
    EXPECT_EQ(content.find(token), std::string::npos) << "the token is in " << entry.path();
  }
  EXPECT_GE(files, 3);  // at least the CSV, its sidecar, the report
  bench.Signal(SIGTERM);
  EXPECT_EQ(bench.WaitExit(10.0), 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest
