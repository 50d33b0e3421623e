// A run with a stateful FMU stopped (Ctrl-C) and resumed gives the uninterrupted journal: the
// FMU state travels in the run state (fmi2SerializeFMUstate) and is restored into a fresh
// instance. The Maxwell FMU's dashpot is soft, so a lost state would show in the journal.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <csignal>

#include "fmi/fmi_test_support.h"
#include "integration/resume_support.h"

namespace hybridtest::testing {
namespace {

TEST(FmuResume, StoppedAndResumedEqualsUninterrupted) {
  const fs::path dir = ResumeTestDir("fmu_resume");
  test_support::WriteText(
      dir / "maxwell.yaml",
      fmt::format("model: {{name: rotor, blades: 3}}\nintegrator: {{tableau: heun, dt: 0.001}}\n"
                  "duration: 20\nsubstructures:\n  r1: {{type: fmu, fmu: {}, displacement: x, "
                  "force: F, parameters: {{k: 7200, c: 50}}}}\n",
                  fmi::test::TestFmu("maxwell")));
  const std::string config = (dir / "maxwell.yaml").string();
  RunToEnd(RunArgs(config, dir / "whole.csv"), dir / "whole.log");
  const fs::path csv = dir / "stopped.csv";
  if (!RunAndSignalAt(RunArgs(config, csv), csv, 200000, SIGINT, dir / "run.log", 130)) {
    GTEST_SKIP() << "the run ended before the signal";
  }
  const auto stopped_rows = ReadLines(csv).size();
  const auto whole = ReadLines(dir / "whole.csv");
  ASSERT_LT(stopped_rows, whole.size());
  const auto [status, out] = Resume(csv, {"--quiet"}, dir / "resume.log");
  ASSERT_EQ(status, 0) << out;
  ExpectSameJournal(whole, ReadLines(csv), false);
}

}  // namespace
}  // namespace hybridtest::testing
