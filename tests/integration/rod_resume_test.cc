// `hybridtest resume` of a specimen on two actuators through the large-displacement setup
// (examples/06_blade_two_actuators/large-displacement.yaml, shortened to 3 s): a run killed
// (SIGKILL) at a random point, then resumed, ends with the journal of an uninterrupted run in
// every channel but the bench's lab time, and both actuators are re-imposed once, at the
// commands of the rods' lengths the journal holds.
#include <fstream>

#include "hybridtest/io/run_reader.h"
#include "integration/resume_support.h"

namespace hybridtest::testing {
namespace {

const std::string kExample = kSource + "/examples/06_blade_two_actuators/";

// The example in `dir`, 3 s long (3,001 rows), with its model and bench files beside it.
std::string ShortExample(const fs::path& dir) {
  std::ifstream in(kExample + "large-displacement.yaml");
  std::string text, line;
  while (std::getline(in, line)) text += line + "\n";
  const std::string from = "duration: 10.0";
  text.replace(text.find(from), from.size(), "duration: 3.0");
  for (const char* f : {"blade_tip.yaml", "bench-2act.yaml"}) {
    fs::copy_file(kExample + f, dir / f, fs::copy_options::overwrite_existing);
  }
  const fs::path config = dir / "large-displacement.yaml";
  std::ofstream(config) << text;
  return config.string();
}

TEST(RodResume, KilledRunOnTheRodSetupResumesToTheUninterruptedJournal) {
  const fs::path dir = ResumeTestDir("rod-resume");
  const std::string config = ShortExample(dir);
  const fs::path reference = dir / "reference.csv";
  ASSERT_EQ(RunToEnd(RunArgs(config, reference), dir / "reference.log"), 0);
  const auto expected = ReadLines(reference);
  ASSERT_EQ(expected.size(), 3002u);  // header + 3,001 rows
  const auto size = fs::file_size(reference);
  auto generator = TrialGenerator();
  std::uniform_real_distribution<double> fraction(0.2, 0.8);
  int killed = 0;
  for (int trial = 0; trial < 2 && killed == 0; ++trial) {
    const fs::path csv = dir / fmt::format("trial{}.csv", trial);
    const double f = fraction(generator);
    if (!RunAndSignalAt(RunArgs(config, csv), csv,
                        static_cast<std::uintmax_t>(f * static_cast<double>(size)), SIGKILL,
                        dir / "run.log", 128 + SIGKILL)) {
      continue;  // the run was faster than the poll
    }
    ++killed;
    const auto [status, output] = Resume(csv, {}, dir / "resume.log");
    ASSERT_EQ(status, 0) << "killed at " << f << ": " << output;
    ExpectSameJournal(expected, ReadLines(csv), true);
    EXPECT_EQ(Sidecar(csv)["status"], "completed");
    // One re-imposition (stage −1) with both actuators' committed commands of row k.
    const long k = Sidecar(csv)["resumes"][0]["step"].get<long>();
    const io::RunData journal = io::LoadRun(csv.string());
    const io::RunData stages =
        io::LoadRun((csv.parent_path() / (csv.stem().string() + ".stages.csv")).string());
    int reimpositions = 0;
    for (long i = 0; i < stages.num_rows(); ++i) {
      if (stages.Get("stage")(i) != -1.0) continue;
      ++reimpositions;
      for (const char* a : {"blade1_a1_command", "blade1_a2_command"}) {
        EXPECT_EQ(stages.Get(a)(i), journal.Get(a)(k)) << a;
      }
    }
    EXPECT_EQ(reimpositions, 1);
  }
  EXPECT_GE(killed, 1) << "no run was killed before it ended";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::testing
