// `hybridtest resume` with real processes: a run killed (SIGKILL) at random points, then
// resumed, ends with the journal of an uninterrupted run — bit for bit for the numerical
// dummy and the MR-OS/Bouc–Wen and alpha-OS variants; in every channel but the bench's lab
// time for the ideal emulated bench, in process and over TCP. The stage record shows the
// committed commands once each and the single flagged re-imposition (stage −1).
#include "hybridtest/io/run_reader.h"
#include "integration/bench_process.h"
#include "integration/resume_support.h"

namespace hybridtest::testing {
namespace {

// Runs `config` once to the end as the reference, then `trials` times killed at a random
// point and resumed; each resumed journal must equal the reference. `extra()` gives the
// arguments of each run and its resume (a fresh bench server for a remote config: a bench
// holds where the previous run left it).
using ExtraArgs = std::function<std::vector<std::string>()>;
void KillAndResumeTrials(const std::string& name, const std::string& config,
                         const ExtraArgs& extra_args, int trials, bool skip_lab_time,
                         const std::function<void(const fs::path&)>& check = {}) {
  auto extra = extra_args ? extra_args() : std::vector<std::string>{};
  const fs::path dir = ResumeTestDir(name);
  const fs::path reference = dir / "reference.csv";
  std::vector<std::string> args{"run", config, "--out", reference.string(), "--quiet"};
  args.insert(args.end(), extra.begin(), extra.end());
  ASSERT_EQ(RunToEnd(args, dir / "reference.log"), 0);
  const auto expected = ReadLines(reference);
  ASSERT_EQ(expected.size(), 10002u);  // header + 10,001 rows
  const auto size = fs::file_size(reference);
  auto generator = TrialGenerator();
  std::uniform_real_distribution<double> fraction(0.05, 0.95);
  int killed = 0;
  for (int trial = 0; trial < trials; ++trial) {
    const fs::path csv = dir / fmt::format("trial{}.csv", trial);
    if (extra_args) {
      extra = extra_args();
      args.resize(5);
      args.insert(args.end(), extra.begin(), extra.end());
    }
    args[3] = csv.string();
    const double f = fraction(generator);
    if (!RunAndSignalAt(args, csv, static_cast<std::uintmax_t>(f * static_cast<double>(size)),
                        SIGKILL, dir / "run.log", 128 + SIGKILL)) {
      continue;  // the run was faster than the poll: nothing to resume
    }
    ++killed;
    const auto [status, output] = Resume(csv, extra, dir / "resume.log");
    ASSERT_EQ(status, 0) << "trial " << trial << " killed at " << f << ": " << output;
    ExpectSameJournal(expected, ReadLines(csv), skip_lab_time);
    const auto sidecar = Sidecar(csv);
    EXPECT_EQ(sidecar["status"], "completed");
    ASSERT_EQ(sidecar["resumes"].size(), 1u);
    EXPECT_EQ(sidecar["resumes"][0]["previous_status"], "running");
    if (check) check(csv);
  }
  std::cout << "[ " << killed << " of " << trials << " runs killed and resumed ]\n";
  EXPECT_GE(killed, trials / 2) << "too few runs were killed before they ended";
  fs::remove_all(dir);
}

// The stage record after one resume from step k: every committed trial (n, 0) up to step k
// once, one re-imposition (stage −1) with the journal's committed command of row k, and no
// trial of a step before k sent twice.
void ExpectOneReimposition(const fs::path& csv) {
  const auto sidecar = Sidecar(csv);
  const long k = sidecar["resumes"][0]["step"].get<long>();
  const io::RunData journal = io::LoadRun(csv.string());
  const io::RunData stages =
      io::LoadRun((csv.parent_path() / (csv.stem().string() + ".stages.csv")).string());
  const Eigen::VectorXd step = stages.Get("step");
  const Eigen::VectorXd stage = stages.Get("stage");
  const Eigen::VectorXd command = stages.Get("r1_command");
  std::map<std::pair<long, int>, int> count;
  int reimpositions = 0;
  for (long i = 0; i < stages.num_rows(); ++i) {
    if (stage(i) == -1.0) {
      ++reimpositions;
      EXPECT_EQ(static_cast<long>(step(i)), k);
      EXPECT_EQ(command(i), journal.Get("r1_command")(k));
    }
    ++count[{static_cast<long>(step(i)), static_cast<int>(stage(i))}];
  }
  EXPECT_EQ(reimpositions, 1);
  for (const auto& [key, n] : count) {
    const auto [s, st] = key;
    if (st >= 0 && (s < k || (s == k && st == 0))) {
      EXPECT_EQ(n, 1) << "step " << s << " stage " << st;
    }
  }
  for (long n = 0; n <= 10000; ++n) EXPECT_GE((count[{n, 0}]), 1) << "step " << n;
}

TEST(ResumeAfterSigkill, DummyIsBitIdentical) {
  KillAndResumeTrials("dummy", kSource + "/examples/rotor/dummy.yaml", {}, 5, false);
}

TEST(ResumeAfterSigkill, MrOsWithBoucWenIsBitIdentical) {
  KillAndResumeTrials("mros", kSource + "/tests/data/resume-mr-os-bouc-wen.yaml", {}, 2, false);
}

TEST(ResumeAfterSigkill, AlphaOsIsBitIdentical) {
  KillAndResumeTrials("alphaos", kSource + "/tests/data/resume-alpha-os.yaml", {}, 1, false);
}

TEST(ResumeAfterSigkill, IdealEmulatedBenchInProcess) {
  KillAndResumeTrials("emulated", kSource + "/tests/data/resume-emulated-ideal.yaml", {}, 2,
                      true, ExpectOneReimposition);
}

TEST(ResumeAfterSigkill, IdealBenchOverTcpLeftRunning) {
  std::vector<std::unique_ptr<BenchProcess>> benches;  // one per run, left running
  KillAndResumeTrials("remote", kSource + "/examples/rotor/remote.yaml", [&] {
    benches.push_back(std::make_unique<BenchProcess>(
        std::vector<std::string>{"--config", kSource + "/examples/rotor/bench-ideal.yaml"}));
    return std::vector<std::string>{"--bench", fmt::format("127.0.0.1:{}", benches.back()->port())};
  }, 2, true, ExpectOneReimposition);
}

}  // namespace
}  // namespace hybridtest::testing
