// The OpenFresco setup (T, q = Tᵀ f, Tᵀ K0 T, back-projection) against hand computations, and
// its config section.
#include "hybridtest/transfer/openfresco/setup.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/constitutive/linear_spring.h"
#include "hybridtest/transfer/openfresco/setup_config.h"

namespace hybridtest::transfer::openfresco {
namespace {

ExpSetup ContractSetup() {
  ExpSetup s;  // wire mm and N
  s.transform = {0.6, -0.8, -0.6, 0.8};
  s.p0s = {0.020};
  s.stiffness_matrix = {7200.0};
  return s;
}

TEST(OpenFrescoSetup, CommandIsP0PlusTd) {
  const ExpSetup s = ContractSetup();
  const std::vector<double> d{0.0, 0.0, 1.06017, -0.355778};  // [mm]
  // T d = −0.6·1.06017 + 0.8·(−0.355778) = −0.9207244 mm, by hand.
  EXPECT_NEAR(ActuatorCommands(s, d)[0], 0.020 - 0.9207244e-3, 1e-15);
  EXPECT_TRUE(std::isnan(ActuatorCommands(s, std::vector<double>{0, NAN, 0, 0})[0]));
  EXPECT_TRUE(std::isnan(ActuatorCommands(s, std::vector<double>{0, 0, INFINITY, 0})[0]));
}

TEST(OpenFrescoSetup, ForcesAreTTransposeF) {
  const std::vector<double> q = ElementForces(ContractSetup(), std::vector<double>{-6.62921568});  // [N]
  const std::vector<double> expected{-3.977529408, 5.303372544, 3.977529408, -5.303372544};
  ASSERT_EQ(q.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(q[i], expected[i], 1e-12) << i;
}

TEST(OpenFrescoSetup, StiffnessIsColumnMajorTTransposeKT) {
  ExpSetup s = ContractSetup();
  s.transform = {1.0, 2.0, -3.0};  // asymmetric entries to catch a row/column mix-up
  const std::vector<double> K = ElementStiffness(s);  // 7.2 N/mm
  ASSERT_EQ(K.size(), 9u);
  // K(row, col) = t_row · 7.2 · t_col; symmetric, so also check the diagonal and values.
  EXPECT_NEAR(K[0], 7.2, 1e-12);            // (0,0)
  EXPECT_NEAR(K[1], 14.4, 1e-12);           // (1,0)
  EXPECT_NEAR(K[2], -21.6, 1e-12);          // (2,0)
  EXPECT_NEAR(K[4], 28.8, 1e-12);           // (1,1)
  EXPECT_NEAR(K[8], 64.8, 1e-12);           // (2,2)
  EXPECT_NEAR(K[5], K[7], 1e-12);           // (2,1) = (1,2)
}

TEST(OpenFrescoSetup, WireUnitsConvert) {
  ExpSetup s = ContractSetup();
  s.wire_units = BenchUnits{1.0, 1e3, "m", "kN"};
  s.transform = {2.0};
  EXPECT_NEAR(ActuatorCommands(s, std::vector<double>{0.001})[0], 0.022, 1e-15);  // 1 mm as m
  EXPECT_NEAR(ElementForces(s, std::vector<double>{500.0})[0], 1.0, 1e-15);                       // 0.5 kN × 2
  EXPECT_NEAR(ElementStiffness(s)[0], 4 * 7.2, 1e-12);                // kN/m
  EXPECT_NEAR(ElementDisplacement(s, std::vector<double>{0.004})[0], 0.002, 1e-15);                // x / t
}

TEST(OpenFrescoSetup, DisplacementBackProjectionReproducesTheOffset) {
  const ExpSetup s = ContractSetup();
  const std::vector<double> dm = ElementDisplacement(s, std::vector<double>{-0.9207244e-3});
  double td = 0.0;
  for (int i = 0; i < 4; ++i) td += s.transform[i] * dm[i];
  EXPECT_NEAR(td, -0.9207244, 1e-12);  // T d_m = x [mm]
  const std::vector<double> v{1.0, 0.0, 0.0, 0.0};
  const std::vector<double> pv = ProjectOnActuators(s, v);
  double tv = 0.0;
  for (int i = 0; i < 4; ++i) tv += s.transform[i] * pv[i];
  EXPECT_NEAR(tv, 0.6, 1e-12);  // the projection keeps T v
}

TEST(OpenFrescoSetup, InvalidSetupsAreConfigErrors) {
  ExpSetup s = ContractSetup();
  s.transform = {0.0, 0.0};
  EXPECT_THROW(ValidateSetup(s), ConfigError);
  s.transform = {};
  EXPECT_THROW(ValidateSetup(s), ConfigError);
  s.transform = {1.0, NAN};
  EXPECT_THROW(ValidateSetup(s), ConfigError);
  // |t|² of 1e-400 underflows to 0: refused before it can put inf or NaN on the wire.
  s.transform = {1e-200};
  EXPECT_THROW(ValidateSetup(s), ConfigError);
  s.transform = {1e200, 1.0};
  EXPECT_THROW(ValidateSetup(s), ConfigError);
  s.transform = {1e-3};  // a small but sane scale still passes, and its outputs are finite
  EXPECT_NO_THROW(ValidateSetup(s));
  for (double v : ElementDisplacement(s, std::vector<double>{0.001})) EXPECT_TRUE(std::isfinite(v));
  s = ContractSetup();
  s.stiffness_matrix = {-1.0};
  EXPECT_THROW(ValidateSetup(s), ConfigError);
}

EmulatedBenchSpec LinearBench() {
  EmulatedBenchConfig b = DefaultEmulatedBenchConfig();
  b.p0 = 0.020;
  b.specimen = std::make_shared<constitutive::LinearSpring>(7200.0, "test");
  return OneActuatorSpec(b);
}

std::string ErrorOf(const std::string& yaml) {
  try {
    ParseSetup(YAML::Load(yaml), "t.yaml: openfresco", LinearBench());
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(OpenFrescoSetupConfig, ParsesUnitsTransformAndDefaults) {
  const ExpSetup s = ParseSetup(
      YAML::Load("{units: {length: m, force: kN}, transform: [[0.6, -0.8]]}"), "t", LinearBench());
  EXPECT_EQ(s.transform, (std::vector<double>{0.6, -0.8}));
  EXPECT_EQ(s.wire_units.metres_per_length_unit, 1.0);
  EXPECT_EQ(s.wire_units.newtons_per_force_unit, 1e3);
  EXPECT_EQ(s.p0s, (std::vector<double>{0.020}));
  EXPECT_EQ(s.stiffness_matrix, (std::vector<double>{7200.0}));  // the specimen's
  const ExpSetup t = ParseSetup(YAML::Load("{transform: [[1]], initial_stiffness: 5000}"), "t",
                             LinearBench());
  EXPECT_EQ(t.stiffness_matrix, (std::vector<double>{5000.0}));
  EXPECT_EQ(t.wire_units.metres_per_length_unit, 1e-3);  // default mm
}

TEST(OpenFrescoSetupConfig, ErrorsNameTheKey) {
  EXPECT_NE(ErrorOf("{transform: [[1, 2], [3, 4]]}").find("openfresco.transform"),
            std::string::npos);
  EXPECT_NE(ErrorOf("{transform: [1, 2]}").find("one row"), std::string::npos);
  EXPECT_NE(ErrorOf("{units: {length: mm}}").find("transform"), std::string::npos);
  EXPECT_NE(ErrorOf("{transform: [[1]], units: {length: inch}}").find("mm or m"),
            std::string::npos);
  EXPECT_NE(ErrorOf("{transform: [[1]], tranform: 2}").find("tranform"), std::string::npos);
  EXPECT_NE(ErrorOf("{transform: [[0, 0]]}").find("all zero"), std::string::npos);
}

TEST(OpenFrescoSetupConfig, LoadFindsTheSectionAtTopLevelOrInBench) {
  const auto dir = std::filesystem::temp_directory_path() / "hybridtest_openfresco_setup_test";
  std::filesystem::create_directories(dir);
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  EXPECT_EQ(LoadSetup(write("top.yaml", "bench: {}\nopenfresco: {transform: [[2]]}\n"),
                      LinearBench()).transform[0], 2.0);
  EXPECT_EQ(LoadSetup(write("in.yaml", "bench: {openfresco: {transform: [[3]]}}\n"),
                      LinearBench()).transform[0], 3.0);
  EXPECT_THROW(LoadSetup(write("none.yaml", "bench: {}\n"), LinearBench()), ConfigError);
  EXPECT_THROW(LoadSetup(write("both.yaml", "bench: {openfresco: {transform: [[3]]}}\n"
                                            "openfresco: {transform: [[2]]}\n"),
                         LinearBench()), ConfigError);
  // The bench parser accepts (and ignores) the section inside `bench:`.
  EXPECT_NO_THROW(LoadEmulatedBenchConfig((dir / "in.yaml").string()));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::transfer::openfresco
