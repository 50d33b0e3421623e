// `hybridtest resume` after the other ways a run stops: Ctrl-C, a safety stop (refused without
// --after-safety-stop, then resumed), a lost bench (the server killed and restarted where the
// actuator held), and on the noisy cantilever bench (the same rows, values within the noise).
#include <cmath>

#include "hybridtest/io/run_reader.h"
#include "integration/bench_process.h"
#include "integration/resume_support.h"

namespace hybridtest::testing {
namespace {

const std::string kIdealBench = kSource + "/examples/rotor/bench-ideal.yaml";

std::string Address(const BenchProcess& bench) {
  return fmt::format("127.0.0.1:{}", bench.port());
}

// The uninterrupted reference run of `config` against a fresh ideal bench; returns its exit
// status.
int RunReferenceOnFreshBench(const std::string& config, const fs::path& reference,
                             const fs::path& log) {
  BenchProcess clean({"--config", kIdealBench});
  return RunToEnd(RunArgs(config, reference, Address(clean)), log);
}

TEST(ResumeAfterStop, CtrlC) {
  const fs::path dir = ResumeTestDir("sigint");
  const std::string config = kSource + "/tests/data/resume-emulated-ideal.yaml";
  const fs::path reference = dir / "reference.csv";
  ASSERT_EQ(RunToEnd(RunArgs(config, reference), dir / "ref.log"), 0);
  const fs::path csv = dir / "interrupted.csv";
  ASSERT_TRUE(RunAndSignalAt(RunArgs(config, csv), csv,
                             fs::file_size(reference) / 3, SIGINT, dir / "run.log", 130));
  EXPECT_EQ(Sidecar(csv)["statistics"]["stop"]["kind"], "interrupted");
  const auto [status, output] = Resume(csv, {}, dir / "resume.log");
  ASSERT_EQ(status, 0) << output;
  EXPECT_NE(output.find("from step"), std::string::npos) << output;
  ExpectSameJournal(ReadLines(reference), ReadLines(csv), true);
  const auto sidecar = Sidecar(csv);
  EXPECT_EQ(sidecar["status"], "completed");
  EXPECT_EQ(sidecar["resumes"][0]["previous_stop"]["kind"], "interrupted");
  EXPECT_LE(sidecar["resumes"][0]["rows_cut"].get<long>(), 1);  // at most a NaN row
  fs::remove_all(dir);
}

TEST(ResumeAfterStop, SafetyStopNeedsTheOperatorsFlag) {
  const fs::path dir = ResumeTestDir("safety");
  const std::string config = kSource + "/tests/data/faults-remote-force.yaml";
  const fs::path reference = dir / "reference.csv";
  ASSERT_EQ(RunReferenceOnFreshBench(config, reference, dir / "ref.log"), 0);
  // A force spike (a broken wire, say) on command 301 stops the run on force_hard.
  BenchProcess bench({"--config", kIdealBench, "--inject", "spike@301"});
  const std::string address = Address(bench);
  const fs::path csv = dir / "stopped.csv";
  {
    Child run(HybridtestArgv(RunArgs(config, csv, address)), dir / "run.log");
    ASSERT_EQ(run.WaitExit(60.0), 3) << run.output();
  }
  auto [refused, message] = Resume(csv, {"--bench", address}, dir / "resume1.log");
  EXPECT_EQ(refused, 2) << message;
  EXPECT_NE(message.find("--after-safety-stop"), std::string::npos) << message;
  // The cause is understood (a one-off spike): the operator resumes with the flag.
  const auto [status, output] =
      Resume(csv, {"--bench", address, "--after-safety-stop"}, dir / "resume2.log");
  ASSERT_EQ(status, 0) << output;
  ExpectSameJournal(ReadLines(reference), ReadLines(csv), true);
  const auto sidecar = Sidecar(csv);
  EXPECT_EQ(sidecar["resumes"][0]["previous_stop"]["kind"], "safety");
  // The bench protocol reads the actuator (its READ, issue 45): the remote bench's position is
  // recorded (it had been null before the protocol could read), one command (≤ max_increment,
  // 5 mm) from where the resume re-imposed the last committed one.
  const auto& check = sidecar["resumes"][0]["checks"][0];
  ASSERT_TRUE(check["read_position_m"].is_number()) << check.dump();
  EXPECT_NEAR(check["read_position_m"].get<double>(), check["position_m"].get<double>(), 0.005)
      << check.dump();
  fs::remove_all(dir);
}

TEST(ResumeAfterStop, BenchLostAndRestarted) {
  const fs::path dir = ResumeTestDir("benchloss");
  const std::string config = kSource + "/tests/data/ladder-remote.yaml";
  const fs::path reference = dir / "reference.csv";
  ASSERT_EQ(RunReferenceOnFreshBench(config, reference, dir / "ref.log"), 0);
  const fs::path csv = dir / "lost.csv";
  {
    BenchProcess lost({"--config", kIdealBench});
    Child run(HybridtestArgv(RunArgs(config, csv, Address(lost))), dir / "run.log");
    while (fs::exists(csv) == false || fs::file_size(csv) < fs::file_size(reference) / 3) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      if (run.WaitExit(0.0) != -2) break;
    }
    lost.Signal(SIGKILL);
    ASSERT_EQ(run.WaitExit(60.0), 4) << run.output();
  }
  // The restarted bench comes up where the actuator held: the last command it executed.
  const io::RunData stages = io::LoadRun((dir / "lost.stages.csv").string());
  const double held = stages.Get("r1_command")(stages.num_rows() - 1);
  const fs::path restarted_config = dir / "bench-restarted.yaml";
  test_support::WriteText(restarted_config, ReadText(kIdealBench) + fmt::format(
      "  initial_position_mm: {:.17g}\n", held * 1e3));
  BenchProcess restarted({"--config", restarted_config.string()});
  const auto [status, output] =
      Resume(csv, {"--bench", Address(restarted)}, dir / "resume.log");
  ASSERT_EQ(status, 0) << output;
  ExpectSameJournal(ReadLines(reference), ReadLines(csv), true);
  EXPECT_EQ(Sidecar(csv)["resumes"][0]["previous_stop"]["kind"], "transfer");
  fs::remove_all(dir);
}

TEST(ResumeAfterSigkill, NoisyCantileverWithinTheNoise) {
  const fs::path dir = ResumeTestDir("cantilever");
  const std::string config = kSource + "/tests/data/resume-cantilever.yaml";
  const fs::path reference = dir / "reference.csv";
  ASSERT_EQ(RunToEnd(RunArgs(config, reference), dir / "ref.log"), 0);
  const fs::path csv = dir / "killed.csv";
  ASSERT_TRUE(RunAndSignalAt(RunArgs(config, csv), csv,
                             fs::file_size(reference) / 2, SIGKILL, dir / "run.log", 128 + SIGKILL));
  const auto [status, output] = Resume(csv, {}, dir / "resume.log");
  ASSERT_EQ(status, 0) << output;
  const io::RunData a = io::LoadRun(reference.string());
  const io::RunData b = io::LoadRun(csv.string());
  ASSERT_EQ(b.num_rows(), a.num_rows());
  EXPECT_EQ(b.Get("t"), a.Get("t"));  // the same rows, no time repeated or missing
  // The re-imposition draws load-cell samples the uninterrupted run did not: from there on
  // the force differs by the averaged noise (σ/√500 ≈ 0.009 N, quantised to 0.01 N), and the
  // motion by what that force does in the rest of the run.
  EXPECT_LT((b.Get("r1") - a.Get("r1")).cwiseAbs().maxCoeff(), 0.2);  // [N], of ~100 N
  EXPECT_LT((b.Get("q1") - a.Get("q1")).cwiseAbs().maxCoeff(), 1e-4);  // [m]
  const auto check = Sidecar(csv)["resumes"][0]["checks"][0];
  EXPECT_LE(std::abs(check["force_N"].get<double>() - check["committed_force_N"].get<double>()),
            check["tolerance_N"].get<double>());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::testing
