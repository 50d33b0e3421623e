// The contract of examples/fmi/ (issue 35), with the binary: the spring FMU's run equals the
// pure simulation within 1e-9 m; the Bouc-Wen FMU's Heun and MR-OS runs finish, and a run
// killed (SIGKILL) and resumed gives the uninterrupted journal. The configs are the example
// files themselves, with only the FMU path pointed at this build's FMUs
// (HYBRIDTEST_EXAMPLE_FMU_DIR, build/release/examples/fmi/ for the release preset).
#include <gtest/gtest.h>

#include <csignal>
#include <cmath>
#include <fstream>
#include <sstream>

#include "integration/resume_support.h"
#include "support/temp_dir.h"

namespace hybridtest::testing {
namespace {

std::string Slurp(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// examples/fmi/<name> copied into `dir` with its FMU path made this build's.
std::string ExampleConfig(const std::string& name, const fs::path& dir) {
  std::string text = Slurp(fs::path(kSource) / "examples" / "fmi" / name);
  const std::string from = "../../build/release/examples/fmi/";
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << name << " does not name the built FMU";
  if (at != std::string::npos) {
    text.replace(at, from.size(), std::string(HYBRIDTEST_EXAMPLE_FMU_DIR) + "/");
  }
  const fs::path out = dir / name;
  test_support::WriteText(out, text);
  return out.string();
}

// Column `name` of the journal `lines` as numbers.
std::vector<double> Column(const std::vector<std::string>& lines, const std::string& name) {
  const auto header = SplitCsv(lines.at(0));
  const auto c = std::find(header.begin(), header.end(), name) - header.begin();
  EXPECT_LT(c, static_cast<long>(header.size())) << "no column " << name;
  std::vector<double> values;
  for (std::size_t i = 1; i < lines.size(); ++i) values.push_back(std::stod(SplitCsv(lines[i]).at(c)));
  return values;
}

TEST(FmuExamples, SpringFmuRunEqualsTheSimulation) {
  const fs::path dir = ResumeTestDir("fmu_example_spring");
  const std::string config = ExampleConfig("rotor-spring-fmu.yaml", dir);
  RunToEnd(RunArgs(config, dir / "fmu.csv"), dir / "fmu.log");
  RunToEnd({"simulate", kSource + "/examples/rotor/numerical.yaml", "--out",
            (dir / "numerical.csv").string(), "--quiet"},
           dir / "numerical.log");
  const auto fmu = ReadLines(dir / "fmu.csv");
  const auto numerical = ReadLines(dir / "numerical.csv");
  ASSERT_EQ(fmu.size(), numerical.size());
  ASSERT_EQ(fmu.size(), 10002u);  // header, t = 0 and 10 000 steps
  double largest = 0.0;
  for (const char* q : {"q1", "q2", "q3", "q4"}) {
    const auto a = Column(fmu, q);
    const auto b = Column(numerical, q);
    for (std::size_t i = 0; i < a.size(); ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
  }
  EXPECT_LE(largest, 1e-9) << "largest |q_fmu - q_simulate| [m or rad]";
  // The blade moved: the comparison is not between two zero runs.
  const auto q1 = Column(numerical, "q1");
  EXPECT_GT(*std::max_element(q1.begin(), q1.end()), 1e-4);
}

TEST(FmuExamples, BoucWenFmuRunsFinishUnderHeunAndMrOs) {
  const fs::path dir = ResumeTestDir("fmu_example_bouc_wen");
  for (const char* name : {"rotor-bouc-wen-fmu.yaml", "rotor-bouc-wen-fmu-mr-os.yaml"}) {
    const std::string config = ExampleConfig(name, dir);
    const fs::path csv = dir / (std::string(name) + ".csv");
    ASSERT_EQ(RunToEnd(RunArgs(config, csv), dir / "run.log"), 0) << name;
    const auto lines = ReadLines(csv);
    ASSERT_GT(lines.size(), 1000u) << name;
    // The blade yielded: its force is below the elastic k q somewhere (hysteresis).
    const auto q = Column(lines, "q1");
    const auto r = Column(lines, "r1");
    double elastic_gap = 0.0;
    for (std::size_t i = 0; i < q.size(); ++i) {
      elastic_gap = std::max(elastic_gap, std::abs(7200.0 * q[i] - r[i]));
    }
    EXPECT_GT(elastic_gap, 1.0) << name << ": the Bouc-Wen FMU never left its elastic branch";
  }
}

// Heun and MR-OS (whose journal also has the intermediate rows of its substeps).
TEST(FmuExamples, BoucWenFmuRunKilledAndResumedEqualsUninterrupted) {
  const fs::path dir = ResumeTestDir("fmu_example_resume");
  for (const std::string name : {"rotor-bouc-wen-fmu.yaml", "rotor-bouc-wen-fmu-mr-os.yaml"}) {
    SCOPED_TRACE(name);
    const std::string config = ExampleConfig(name, dir);
    const fs::path whole_csv = dir / (name + ".whole.csv");
    RunToEnd(RunArgs(config, whole_csv), dir / "whole.log");
    const auto whole = ReadLines(whole_csv);
    const fs::path csv = dir / (name + ".killed.csv");
    if (!RunAndSignalAt(RunArgs(config, csv), csv, fs::file_size(whole_csv) / 2, SIGKILL,
                        dir / "run.log", 128 + SIGKILL)) {
      GTEST_SKIP() << name << ": the run ended before the kill";
    }
    ASSERT_LT(ReadLines(csv).size(), whole.size());
    const auto [status, out] = Resume(csv, {"--quiet"}, dir / "resume.log");
    ASSERT_EQ(status, 0) << out;
    ExpectSameJournal(whole, ReadLines(csv), false);
  }
}

}  // namespace
}  // namespace hybridtest::testing
