// Constraint forces (multibody/constraints.h CalcConstraintForces, model files'
// `record_force:`): the multipliers equal the tension of a mass on a rod (analytical), the
// multipliers of the augmented system [M −Bᵀ; B 0] (an independent algorithm) whichever speeds
// are dependent, and the bicycle's ground force under its front wheel at steady upright
// rolling (a moment balance about the rear contact); their units follow the constraint's.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/assembly.h"
#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/kane.h"
#include "support/temp_dir.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;
using multibody::Data;
using multibody::Model;
const std::string kSource = HYBRIDTEST_SOURCE_DIR;

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

models::BuiltModel BuildText(const std::string& text, const std::string& name,
                             const std::map<std::string, double>& set = {}) {
  static const fs::path dir = test_support::FreshTempDir("constraint_forces");
  const fs::path path = dir / name;
  std::ofstream(path) << text;
  const modelfile::ModelFile file = modelfile::LoadModelFile(path.string());
  models::ParameterSet parameters = file.parameters;
  for (const auto& [key, value] : set) parameters.Set(key, value, "the test");
  return modelfile::BuildModelFile(file, parameters);
}

// A mass m on a massless rod of length l pinned at O, written in Cartesian coordinates: the
// rod is the holonomic constraint sqrt(x² + y²) − l = 0 (in m, so its force is in N).
const char* kTetheredMass = R"(name: tethered_mass
parameters:
  m: {value: 2.0, unit: kg}
  l: {value: 0.8, unit: m}
  g: {value: 9.81, unit: m/s²}
coordinates:
  - {name: x, unit: m, initial: 0.4}
  - {name: y, unit: m, initial: -0.69}
speeds:
  - {name: vx, unit: m/s}
  - {name: vy, unit: m/s}
points:
  - {name: P, from: O, frame: N, position: [x, y, 0]}
particles:
  - {name: bob, point: P, mass: m}
forces:
  - {name: gravity, point: P, value: [0, -m * g, 0]}
constraints:
  - {name: rod, holonomic: "sqrt(x^2 + y^2) - l", record_force: true}
)";

// λ at (t, x) after the constrained derivative.
Eigen::VectorXd Forces(const Model& model, const Eigen::VectorXd& x, Data<double>& data) {
  Eigen::VectorXd xdot(model.num_states());
  multibody::CalcStateDerivative<double>(model, data, 0.0, x,
                                         Eigen::VectorXd::Zero(model.num_slots()), xdot);
  Eigen::VectorXd lambda(model.num_constraint_rows());
  multibody::CalcConstraintForces(model, data, lambda);
  return lambda;
}

TEST(ConstraintForces, TheRodOfATetheredMassCarriesItsAnalyticalTension) {
  const models::BuiltModel built = BuildText(kTetheredMass, "tethered_mass.yaml");
  const Model& model = built.model;
  ASSERT_EQ(model.num_constraint_rows(), 1);
  EXPECT_TRUE(model.constraints()[0].record_force);
  EXPECT_EQ(model.constraints()[0].force_unit, "N");
  const double m = 2.0, l = 0.8, g = 9.81;
  Data<double> data(model);
  for (const double theta : {0.0, 0.3, -1.1, 2.0}) {      // from the downward vertical [rad]
    for (const double omega : {0.0, 1.5, -4.0}) {          // θ̇ [rad/s]
      Eigen::VectorXd x(4);
      x << l * std::sin(theta), -l * std::cos(theta), l * omega * std::cos(theta),
          l * omega * std::sin(theta);
      // The rod pulls the mass towards O with T = m (g cos θ + l θ̇²); the constraint's
      // gradient points away from O, so λ = −T.
      const double tension = m * (g * std::cos(theta) + l * omega * omega);
      const double lambda = Forces(model, x, data)(0);
      EXPECT_NEAR(lambda, -tension, 1e-12 * (1.0 + std::abs(tension)))
          << "θ = " << theta << " rad, θ̇ = " << omega << " rad/s";
    }
  }
}

// λ of M u̇ = g + Bᵀλ, B u̇ = −bias, solved as one augmented system.
Eigen::VectorXd AugmentedMultipliers(const Model& model, const Eigen::VectorXd& x) {
  Data<double> data(model);
  const int n = model.num_coordinates();
  const int m = model.num_constraint_rows();
  multibody::CalcKinematics<double>(model, data, 0.0, x);
  multibody::CalcMassMatrixPairwise(model, data);
  multibody::CalcForcing<double>(model, data, Eigen::VectorXd::Zero(model.num_slots()));
  multibody::CalcConstraints(model, data);
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n + m, n + m);
  K.topLeftCorner(n, n) = data.M;
  K.topRightCorner(n, m) = -data.constraint_B.transpose();
  K.bottomLeftCorner(m, n) = data.constraint_B;
  Eigen::VectorXd rhs(n + m);
  rhs << data.g, -data.constraint_bias;
  return Eigen::FullPivLU<Eigen::MatrixXd>(K).solve(rhs).tail(m);
}

TEST(ConstraintForces, EqualTheMultipliersOfTheAugmentedSystemWhicheverSpeedsAreDependent) {
  std::string text = ReadText(kSource + "/examples/models/slider_crank.yaml");
  for (const bool pivoted : {false, true}) {
    const std::string edited =
        pivoted ? std::regex_replace(text, std::regex("dependent_speeds: \\[u2, u3\\]"), "") : text;
    const models::BuiltModel built = BuildText(edited, "slider_crank.yaml");
    const Model& model = built.model;
    EXPECT_EQ(model.constraint_options().dependent_speeds.empty(), pivoted);
    Data<double> data(model);
    for (const double crank : {0.2, 1.4, 2.9, 4.4}) {
      Eigen::VectorXd x = model.initial_state();
      x(0) = crank;
      x(3) = -6.0 + crank;
      x = multibody::AssembleState(model, 0.0, x).x;
      const Eigen::VectorXd lambda = Forces(model, x, data);
      const Eigen::VectorXd reference = AugmentedMultipliers(model, x);
      EXPECT_LT((lambda - reference).cwiseAbs().maxCoeff(), 1e-9 * (1.0 + reference.norm()))
          << "pivoted " << pivoted << " crank " << crank << ": " << lambda.transpose()
          << " vs " << reference.transpose();
    }
  }
}

TEST(ConstraintForces, TheBicyclesFrontWheelCarriesItsShareOfTheWeightAtSteadyRolling) {
  std::string text = ReadText(kSource + "/examples/models/whipple_bicycle.yaml");
  text = std::regex_replace(text, std::regex("(name: front touches ground, [^}]*)\\}"),
                            "$1, record_force: true}");
  text = std::regex_replace(text, std::regex("(name: front rolling, [^}]*)\\}"),
                            "$1, record_force: true}");
  for (const double v : {0.0, 5.0}) {
    const models::BuiltModel built = BuildText(text, "bicycle.yaml", {{"v", v}});
    const Model& model = built.model;
    const Eigen::VectorXd x = multibody::AssembleState(model, 0.0, model.initial_state()).x;
    Data<double> data(model);
    const Eigen::VectorXd lambda = Forces(model, x, data);
    // Upright and straight at constant speed nothing accelerates: the moments about the rear
    // contact give the front normal force N_F = g Σ m_i x_i / w (Meijaard et al.'s Table 1:
    // rear wheel at x = 0, frame at 0.3 m, fork at 0.9 m, front wheel at w = 1.02 m).
    const double normal = 9.81 * (2.0 * 0.0 + 85.0 * 0.3 + 4.0 * 0.9 + 3.0 * 1.02) / 1.02;
    int ground = -1;
    for (int row = 0; row < model.num_constraint_rows(); ++row) {
      const std::string name = multibody::ConstraintRowName(model, row);
      if (name == "front touches ground (z)") ground = row;
      if (name.starts_with("front rolling") || name.starts_with("rear rolling")) {
        EXPECT_NEAR(lambda(row), 0.0, 1e-9 * normal) << name << " at v = " << v;
      }
    }
    ASSERT_GE(ground, 0);
    // z points down: the ground pushes the wheel up.
    EXPECT_NEAR(lambda(ground), -normal, 1e-9 * normal) << "v = " << v << " m/s";
  }
}

TEST(ConstraintForces, TheirUnitFollowsTheConstraint) {
  // An angle constraint carries a moment; a velocity constraint in m/s a force; one in rad/s
  // a moment.
  std::string text = kTetheredMass;
  text = std::regex_replace(text, std::regex("holonomic: \"sqrt\\(x\\^2 \\+ y\\^2\\) - l\""),
                            "holonomic: \"atan2(x, -y) - 0.5\"");
  EXPECT_EQ(BuildText(text, "angle.yaml").model.constraints()[0].force_unit, "N·m");
  std::string velocity = kTetheredMass;
  velocity = std::regex_replace(velocity, std::regex("holonomic: \"sqrt\\(x\\^2 \\+ y\\^2\\) - l\""),
                                "nonholonomic: \"vx - 0.1 * vy\"");
  EXPECT_EQ(BuildText(velocity, "velocity.yaml").model.constraints()[0].force_unit, "N");
  velocity = std::regex_replace(velocity, std::regex("\"vx - 0.1 \\* vy\""), "\"(vx - vy) / l\"");
  EXPECT_EQ(BuildText(velocity, "rate.yaml").model.constraints()[0].force_unit, "N·m");
}

TEST(ConstraintForces, ABadRecordForceIsRefusedAtItsLine) {
  std::string text = kTetheredMass;
  text = std::regex_replace(text, std::regex("record_force: true"), "record_force: yes please");
  try {
    (void)BuildText(text, "bad_record.yaml");
    FAIL() << "record_force: yes please was accepted";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bad_record.yaml:19"), std::string::npos) << what;
    EXPECT_NE(what.find("record_force"), std::string::npos) << what;
    EXPECT_NE(what.find("true"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace hybridtest
