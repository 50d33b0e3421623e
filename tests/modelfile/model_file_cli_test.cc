// Model files through the real `hybridtest` binary: `eom` on the rotor's model file gives the
// built-in rotor's JSON within 1e-12; `check-model` exits 0 on a valid file and 2 naming
// file:line on an invalid one; the wind turbine's dummy hybrid test equals its simulation bit
// for bit and records its N·m slot in the sidecar.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "support/run_command.h"
#include "support/temp_dir.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;
const std::string kSource = HYBRIDTEST_SOURCE_DIR;

// Runs `hybridtest ARGS` (stdout only unless `merge`); returns (exit status, output).
std::pair<int, std::string> Hybridtest(const std::string& args, bool merge = true) {
  return testing::RunCommand(std::string(HYBRIDTEST_BINARY) + " " + args, 300, merge);
}

// One directory per test process, made on first use.
fs::path TempDir() {
  static const fs::path dir = test_support::FreshTempDir("modelfile");
  return dir;
}

double MaxRelative(const nlohmann::json& a, const nlohmann::json& b) {
  if (a.is_array()) {
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, MaxRelative(a[i], b[i]));
    return worst;
  }
  const double x = a.get<double>(), y = b.get<double>();
  return std::abs(x - y) / std::max(1.0, std::abs(y));
}

TEST(ModelFileCliTest, EomOnTheRotorFileEqualsTheBuiltInRotor) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    std::string state;
    for (int i = 0; i < 8; ++i) {
      const double scale = i < 3 ? 0.05 : (i == 3 ? 3.0 : 5.0);
      state += fmt::format("{}{:.17g}", i ? "," : "", scale * unit(rng));
    }
    const std::string args = fmt::format("--time {} --state={} --json", 0.4 * trial, state);
    const auto [s1, file] =
        Hybridtest(fmt::format("eom {}/examples/01_rotor_model_file/numerical.yaml {}", kSource, args), false);
    const auto [s2, builtin] =
        Hybridtest(fmt::format("eom {}/examples/rotor/numerical.yaml {}", kSource, args), false);
    ASSERT_EQ(s1, 0) << file;
    ASSERT_EQ(s2, 0) << builtin;
    const nlohmann::json a = nlohmann::json::parse(file), b = nlohmann::json::parse(builtin);
    for (const char* key : {"mass_matrix", "forcing", "xdot", "restoring"}) {
      EXPECT_LT(MaxRelative(a[key], b[key]), 1e-12) << key << " at " << args;
    }
  }
}

// Issue 50: `eom` called the right-hand side "forcing g" where `equations` calls it f.
TEST(ModelFileCliTest, EomAndEquationsNameTheRightHandSideF) {
  const std::string model = kSource + "/examples/01_rotor_model_file/numerical.yaml";
  const auto [status, out] = Hybridtest(
      fmt::format("eom {} --time 0 --state 0,0,0,0,0,0,0,0", model), false);
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find("M u̇ = f"), std::string::npos) << out;
  EXPECT_NE(out.find("right-hand side f"), std::string::npos) << out;
  EXPECT_EQ(out.find("forcing g"), std::string::npos) << out;
}

TEST(ModelFileCliTest, CheckModelExitsZeroOnAValidFile) {
  const auto [status, out] =
      Hybridtest(fmt::format("check-model {}/examples/models/double_pendulum.yaml --no-sympy", kSource));
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("coordinates (2)"), std::string::npos) << out;
  EXPECT_NE(out.find("positive definite"), std::string::npos) << out;
}

TEST(ModelFileCliTest, CheckModelExitsTwoNamingFileLineAndTheFixOnAnInvalidFile) {
  const fs::path bad = TempDir() / "bad.yaml";
  std::ofstream(bad) << "name: bad\n"
                        "parameters:\n  l: {value: 1.0, unit: m}\n  m: {value: 2.0, unit: kg}\n"
                        "coordinates:\n  - {name: theta, unit: rad}\n"
                        "frames:\n  - {name: A, parent: N, axis: z, angle: theta}\n"
                        "points:\n  - {name: P, from: O, frame: A, position: [lenght, 0, 0]}\n"
                        "particles:\n  - {name: bob, point: P, mass: m}\n";
  const auto [status, out] = Hybridtest("check-model " + bad.string());
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find(bad.string() + ":10: points[0].position[0]"), std::string::npos) << out;
  EXPECT_NE(out.find("'lenght'"), std::string::npos) << out;
  EXPECT_NE(out.find("did you mean l"), std::string::npos) << out;
}

TEST(ModelFileCliTest, CheckModelExitsTwoOnABodyWithoutMassOrASlotWithoutStiffness) {
  const std::string head = "name: bad\n"                                          // 1
                           "coordinates:\n  - {name: x, unit: m}\n"              // 2-3
                           "points:\n  - {name: P, position: [x, 0, 0]}\n";      // 4-5
  const fs::path no_mass = TempDir() / "no_mass.yaml";
  std::ofstream(no_mass) << head << "bodies:\n  - {name: b, frame: N, mass_center: P, inertia: [0, 0, 0]}\n";
  const auto [s1, o1] = Hybridtest("check-model " + no_mass.string());
  EXPECT_EQ(s1, 2) << o1;
  EXPECT_NE(o1.find(no_mass.string() + ":7: bodies[0].mass: missing"), std::string::npos) << o1;
  const fs::path no_stiffness = TempDir() / "no_stiffness.yaml";
  std::ofstream(no_stiffness) << head << "particles:\n  - {name: p, point: P, mass: 1}\n"
                              << "slots:\n  - {name: r1, unit: N, displacement: x}\n";
  const auto [s2, o2] = Hybridtest("check-model " + no_stiffness.string());
  EXPECT_EQ(s2, 2) << o2;
  EXPECT_NE(o2.find(no_stiffness.string() + ":9: slots[0].stiffness: missing"), std::string::npos) << o2;
}

TEST(ModelFileCliTest, CheckModelNamesTheCoordinateOfASingularMassMatrix) {
  const fs::path f = TempDir() / "singular.yaml";
  std::ofstream(f) << "name: singular\n"
                      "coordinates:\n  - {name: x, unit: m}\n  - {name: forgotten, unit: rad}\n"
                      "points:\n  - {name: P, position: [x, 0, 0]}\n"
                      "particles:\n  - {name: p, point: P, mass: 1}\n";
  const auto [status, out] = Hybridtest("check-model --no-sympy " + f.string());
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("not positive definite"), std::string::npos) << out;
  EXPECT_NE(out.find("involves forgotten: give it mass or inertia"), std::string::npos) << out;
}

TEST(ModelFileCliTest, CheckModelSaysWhenWIsSingular) {
  const fs::path f = TempDir() / "singular_w.yaml";
  std::ofstream(f) << "name: singular_w\n"
                      "coordinates:\n  - {name: x, unit: m}\n  - {name: y, unit: m}\n"
                      "kinematical_equations:\n  - [1, 0]\n  - [1, 0]\n"
                      "points:\n  - {name: P, position: [x, y, 0]}\n"
                      "particles:\n  - {name: p, point: P, mass: 1}\n";
  const auto [status, out] = Hybridtest("check-model --no-sympy " + f.string());
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("W(q) of q̇ = W(q) u is singular"), std::string::npos) << out;
}

TEST(ModelFileCliTest, CheckModelReportsTheSympyTimeLimitInWords) {
  const auto [status, out] = Hybridtest(fmt::format(
      "check-model {}/examples/models/double_pendulum.yaml --sympy-timeout 0.001", kSource));
  if (out.find("sympy: skipped") != std::string::npos) GTEST_SKIP() << "no python3 with SymPy";
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("did not finish within 0.001 s"), std::string::npos) << out;
  EXPECT_EQ(out.find("exit status"), std::string::npos) << out;
}

std::string ReadFile(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(ModelFileCliTest, WindTurbineDummyHybridTestEqualsItsSimulation) {
  const fs::path sim = TempDir() / "wt_sim.csv", dummy = TempDir() / "wt_dummy.csv";
  const std::string dir = kSource + "/examples/04_wind_turbine/";
  const auto [s1, o1] = Hybridtest(fmt::format("simulate {}simulation.yaml --out {}", dir, sim.string()));
  const auto [s2, o2] = Hybridtest(fmt::format("run {}dummy.yaml --out {}", dir, dummy.string()));
  ASSERT_EQ(s1, 0) << o1;
  ASSERT_EQ(s2, 0) << o2;
  // Same channels and values, row by row (the journal prints 17 significant digits).
  EXPECT_EQ(ReadFile(sim), ReadFile(dummy));
  const nlohmann::json meta = nlohmann::json::parse(ReadFile(TempDir() / "wt_dummy.meta.json"));
  const nlohmann::json& slots = meta["model"]["slots"];
  ASSERT_EQ(slots.size(), 3u);
  EXPECT_EQ(slots[0]["name"], "r1");
  EXPECT_EQ(slots[0]["unit"], "N·m");
  EXPECT_EQ(meta["model"]["name"], "wind_turbine");
}

// Issue 19's turbine example: three flapping blades by repeat:, Cp/Ct tables, a PI generator
// torque with its integrator and speed filter as extra states; the dummy hybrid test of blade
// 1's root equals the simulation bit for bit, and the journal carries the extra states.
TEST(ModelFileCliTest, TurbineLabDummyHybridTestEqualsItsSimulation) {
  const fs::path sim = TempDir() / "tl_sim.csv", dummy = TempDir() / "tl_dummy.csv";
  const std::string dir = kSource + "/examples/05_turbine_lab/";
  const auto [s1, o1] = Hybridtest(fmt::format("simulate {}simulation.yaml --out {}", dir, sim.string()));
  const auto [s2, o2] = Hybridtest(fmt::format("run {}dummy.yaml --out {}", dir, dummy.string()));
  ASSERT_EQ(s1, 0) << o1;
  ASSERT_EQ(s2, 0) << o2;
  const std::string a = ReadFile(sim), b = ReadFile(dummy);
  EXPECT_EQ(a, b);
  const std::string header = a.substr(0, a.find('\n'));
  EXPECT_NE(header.find("w3,w_f,z_q,r1,r2,r3"), std::string::npos) << header;
  const nlohmann::json meta = nlohmann::json::parse(ReadFile(TempDir() / "tl_dummy.meta.json"));
  ASSERT_EQ(meta["model"]["extra_states"].size(), 2u);
  EXPECT_EQ(meta["model"]["extra_states"][1]["name"], "z_q");
  EXPECT_EQ(meta["model"]["extra_states"][1]["unit"], "rad");
}

}  // namespace
}  // namespace hybridtest
