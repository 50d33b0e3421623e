// `hybridtest resume` of a specimen on two actuators (examples/06_blade_two_actuators): a run
// killed (SIGKILL) at a random point, then resumed, ends with the journal of an uninterrupted
// run in every channel but the bench's lab time (the re-imposition counts there), for the
// linear and the yielding (biaxial Bouc–Wen) specimen: every actuator is re-imposed, once.
#include "hybridtest/io/run_reader.h"
#include "integration/resume_support.h"

namespace hybridtest::testing {
namespace {

const std::string kExample = kSource + "/examples/06_blade_two_actuators/";

// The stage record after one resume from step k: one re-imposition (stage −1) carrying every
// actuator's committed command of journal row k.
void ExpectEveryActuatorReimposedOnce(const fs::path& csv) {
  const long k = Sidecar(csv)["resumes"][0]["step"].get<long>();
  const io::RunData journal = io::LoadRun(csv.string());
  const io::RunData stages =
      io::LoadRun((csv.parent_path() / (csv.stem().string() + ".stages.csv")).string());
  const Eigen::VectorXd stage = stages.Get("stage");
  int reimpositions = 0;
  for (long i = 0; i < stages.num_rows(); ++i) {
    if (stage(i) != -1.0) continue;
    ++reimpositions;
    EXPECT_EQ(static_cast<long>(stages.Get("step")(i)), k);
    for (const char* a : {"blade1_a1_command", "blade1_a2_command"}) {
      EXPECT_EQ(stages.Get(a)(i), journal.Get(a)(k)) << a;
    }
  }
  EXPECT_EQ(reimpositions, 1);
}

void KillAndResume(const std::string& name, const std::string& config, int trials) {
  const fs::path dir = ResumeTestDir(name);
  const fs::path reference = dir / "reference.csv";
  ASSERT_EQ(RunToEnd(RunArgs(config, reference), dir / "reference.log"), 0);
  const auto expected = ReadLines(reference);
  ASSERT_EQ(expected.size(), 10002u);  // header + 10,001 rows
  const auto size = fs::file_size(reference);
  auto generator = TrialGenerator();
  std::uniform_real_distribution<double> fraction(0.1, 0.9);
  int killed = 0;
  for (int trial = 0; trial < trials; ++trial) {
    const fs::path csv = dir / fmt::format("trial{}.csv", trial);
    const double f = fraction(generator);
    if (!RunAndSignalAt(RunArgs(config, csv), csv,
                        static_cast<std::uintmax_t>(f * static_cast<double>(size)), SIGKILL,
                        dir / "run.log", 128 + SIGKILL)) {
      continue;  // the run was faster than the poll
    }
    ++killed;
    const auto [status, output] = Resume(csv, {}, dir / "resume.log");
    ASSERT_EQ(status, 0) << "trial " << trial << " killed at " << f << ": " << output;
    ExpectSameJournal(expected, ReadLines(csv), true);
    EXPECT_EQ(Sidecar(csv)["status"], "completed");
    ExpectEveryActuatorReimposedOnce(csv);
  }
  std::cout << "[ " << killed << " of " << trials << " runs killed and resumed ]\n";
  EXPECT_GE(killed, 1) << "no run was killed before it ended";
  fs::remove_all(dir);
}

TEST(MultiActuatorResume, LinearSpecimenOnTwoActuators) {
  KillAndResume("multi-linear", kExample + "emulated.yaml", 2);
}

TEST(MultiActuatorResume, YieldingSpecimenOnTwoActuators) {
  KillAndResume("multi-bouc-wen", kExample + "bouc-wen.yaml", 2);
}

}  // namespace
}  // namespace hybridtest::testing
