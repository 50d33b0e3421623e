// Constrained models through the real `hybridtest` binary: a 10 s RK4 run of the four-bar
// keeps the loop-closure residual below 1e-8 m (the documented tolerance, decision 0023);
// the slider-crank's dummy hybrid test equals its numerical simulation bit for bit; and the
// three refusals (unmeetable constraint, singular dependent speeds, a velocity constraint not
// linear in u) exit 2 naming file:line; check-model compares the reduced equations with SymPy.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/assembly.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;
const std::string kSource = HYBRIDTEST_SOURCE_DIR;

std::pair<int, std::string> Hybridtest(const std::string& args) {
  return testing::RunCommand(std::string(HYBRIDTEST_BINARY) + " " + args, 300, true);
}

fs::path TempDir() {
  static const fs::path dir = test_support::FreshTempDir("constraints_cli");
  return dir;
}

std::string ReadFile(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(ConstraintsCliTest, FourBarSimulationKeepsTheLoopClosed) {
  const fs::path csv = TempDir() / "four_bar.csv";
  const auto [status, out] = Hybridtest(fmt::format(
      "simulate {}/examples/09_closed_loops/four_bar.yaml --out {}", kSource, csv.string()));
  ASSERT_EQ(status, 0) << out;
  const modelfile::ModelFile file = modelfile::LoadModelFile(kSource + "/examples/models/four_bar.yaml");
  const models::BuiltModel built = modelfile::BuildModelFile(file, file.parameters);
  std::istringstream lines(ReadFile(csv));
  std::string line;
  std::getline(lines, line);  // header: t, q1..q3, u1..u3, ...
  double worst = 0.0, last_t = 0.0, crank_travel = 0.0, first_q1 = 0.0;
  int rows = 0;
  while (std::getline(lines, line)) {
    std::vector<double> v;
    std::stringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) v.push_back(std::stod(cell));
    ASSERT_GE(v.size(), 7u);
    Eigen::VectorXd x(6);
    for (int i = 0; i < 6; ++i) x(i) = v[static_cast<std::size_t>(1 + i)];
    worst = std::max(worst, multibody::CalcConstraintResiduals(built.model, v[0], x).position);
    if (rows == 0) first_q1 = x(0);
    crank_travel = std::max(crank_travel, std::abs(x(0) - first_q1));
    last_t = v[0];
    ++rows;
  }
  EXPECT_NEAR(last_t, 10.0, 1e-9);
  EXPECT_GT(crank_travel, 0.1);  // the mechanism moved
  EXPECT_LT(worst, 1e-8) << "largest loop-closure residual [m] over the run";
}

TEST(ConstraintsCliTest, SliderCrankDummyHybridTestEqualsItsSimulationBitForBit) {
  const fs::path sim = TempDir() / "sc_sim.csv", dummy = TempDir() / "sc_dummy.csv";
  const std::string dir = kSource + "/examples/09_closed_loops/";
  const auto [s1, o1] = Hybridtest(fmt::format("simulate {}slider_crank_simulation.yaml --out {}", dir, sim.string()));
  const auto [s2, o2] = Hybridtest(fmt::format("run {}slider_crank_dummy.yaml --out {}", dir, dummy.string()));
  ASSERT_EQ(s1, 0) << o1;
  ASSERT_EQ(s2, 0) << o2;
  const std::string a = ReadFile(sim), b = ReadFile(dummy);
  EXPECT_GT(a.size(), 1000u);
  EXPECT_EQ(a, b);
}

TEST(ConstraintsCliTest, RefusalsExitTwoNamingFileAndLine) {
  std::string text = ReadFile(kSource + "/examples/models/four_bar.yaml");
  const fs::path bad = TempDir() / "four_bar_bad.yaml";
  std::ofstream(bad) << std::regex_replace(text, std::regex("l0: \\{value: 0.3,"), "l0: {value: 1.0,");
  const auto [status, out] = Hybridtest("modes " + bad.string());
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("four_bar_bad.yaml:"), std::string::npos) << out;
  EXPECT_NE(out.find("cannot be met"), std::string::npos) << out;
  const auto [s2, o2] = Hybridtest(fmt::format("modes {}/examples/models/four_bar.yaml --at q=0.3", kSource));
  EXPECT_EQ(s2, 2) << o2;  // q has 1 value for n = 3
}

// check-model on a constrained file also compares the reduced equations with SymPy, with the
// dependent speeds the engine picked (here by pivoting: the file names none); a tolerance no
// floating-point result meets makes that comparison fail, and check-model with it.
TEST(ConstraintsCliTest, CheckModelComparesTheReducedEquationsWithSympy) {
  std::string text = ReadFile(kSource + "/examples/models/four_bar.yaml");
  const fs::path pivoted = TempDir() / "four_bar_pivoted.yaml";
  std::ofstream(pivoted) << std::regex_replace(text, std::regex("dependent_speeds: \\[u2, u3\\]"), "");
  const auto [status, out] = Hybridtest("check-model " + pivoted.string());
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find("reduced equations with dependent speeds at 5 consistent states, 0 failures"),
            std::string::npos) << out;
  const auto [s2, o2] = Hybridtest(fmt::format(
      "check-model {}/examples/models/slider_crank.yaml --tolerance 1e-30", kSource));
  EXPECT_EQ(s2, 1) << o2;
  EXPECT_NE(o2.find("FAIL: slider_crank.yaml state"), std::string::npos) << o2;
  EXPECT_NE(o2.find("DIFFERENT"), std::string::npos) << o2;
}

}  // namespace
}  // namespace hybridtest
