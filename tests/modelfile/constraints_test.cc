// Constraints in the engine and in model files (multibody/constraints.h, assembly.h): the
// four-bar's loop is closed by assembly; u̇ satisfies the acceleration constraints and equals
// the solution of the multiplier form [M Bᵀ; B 0] (an independent algorithm) whichever speeds
// are dependent; the state Jacobian through the constraints matches central differences; and
// bad constraints are refused naming file:line and the fix.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/assembly.h"
#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/derivatives.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/symbolic/equations.h"
#include "support/augmented_constraints.h"
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

models::BuiltModel BuildText(const std::string& text, const std::string& name) {
  static const fs::path dir = test_support::FreshTempDir("constraints");
  const fs::path path = dir / name;
  std::ofstream(path) << text;
  const modelfile::ModelFile file = modelfile::LoadModelFile(path.string());
  return modelfile::BuildModelFile(file, file.parameters);
}

models::BuiltModel FourBar(const std::string& edit_from = "", const std::string& edit_to = "") {
  std::string text = ReadText(kSource + "/examples/models/four_bar.yaml");
  if (!edit_from.empty()) text = std::regex_replace(text, std::regex(edit_from), edit_to);
  return BuildText(text, "four_bar.yaml");
}

// u̇ from M u̇ = g + Bᵀλ, B u̇ = −bias (no stabilisation needed on the manifold).
Eigen::VectorXd MultiplierSolution(const Model& model, double t, const Eigen::VectorXd& x) {
  return test_support::AugmentedSolution(model, t, x).head(model.num_coordinates());
}

TEST(ConstraintsTest, AssemblyClosesTheFourBarLoop) {
  const models::BuiltModel built = FourBar();
  const Model& model = built.model;
  ASSERT_TRUE(model.has_constraints());
  EXPECT_EQ(model.num_constraint_rows(), 2);
  const Eigen::VectorXd x0 = model.initial_state();
  EXPECT_GT(multibody::CalcConstraintResiduals(model, 0.0, x0).position, 1e-3);  // a guess
  const multibody::AssembledState a = multibody::AssembleState(model, 0.0, x0);
  EXPECT_LT(a.position_residual, 1e-13);
  EXPECT_LT(a.velocity_residual, 1e-13);
  EXPECT_EQ(a.x(0), x0(0));  // the independent coordinate and speed are kept
  EXPECT_EQ(a.x(3), x0(3));
}

TEST(ConstraintsTest, AccelerationsMeetTheConstraintsAndEqualTheMultiplierForm) {
  for (const bool pivoted : {false, true}) {
    const models::BuiltModel built =
        pivoted ? FourBar("dependent_speeds: \\[u2, u3\\]", "") : FourBar();
    const Model& model = built.model;
    EXPECT_EQ(model.constraint_options().dependent_speeds.empty(), pivoted);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    for (int trial = 0; trial < 10; ++trial) {
      Eigen::VectorXd x = model.initial_state();
      x(0) = 1.3 + 0.3 * uni(rng);
      x(3) = 5.0 * uni(rng);
      x = multibody::AssembleState(model, 0.0, x).x;
      Data<double> data(model);
      Eigen::VectorXd xdot(model.num_states());
      multibody::CalcStateDerivative<double>(model, data, 0.0, x, Eigen::VectorXd(), xdot);
      const Eigen::VectorXd udot = xdot.tail(3);
      const Eigen::VectorXd accel = data.constraint_B * udot + data.constraint_bias;
      EXPECT_LT(accel.cwiseAbs().maxCoeff(), 1e-10);
      const Eigen::VectorXd reference = MultiplierSolution(model, 0.0, x);
      double difference = 0.0;
      for (int k = 0; k < 3; ++k) difference = std::max(difference, std::abs(udot(k) - reference(k)));
      EXPECT_LT(difference, 1e-9 * (1.0 + reference.norm()))
          << "pivoted " << pivoted << " trial " << trial;
    }
  }
}

TEST(ConstraintsTest, StateJacobianThroughTheConstraintsMatchesDifferences) {
  const models::BuiltModel built = FourBar();
  const Model& model = built.model;
  const Eigen::VectorXd x = multibody::AssembleState(model, 0.0, model.initial_state()).x;
  const Eigen::VectorXd r = Eigen::VectorXd::Zero(0);
  const Eigen::MatrixXd J = multibody::CalcStateJacobian(model, 0.0, x, r);
  Data<double> data(model);
  const int nx = model.num_states();
  for (int i = 0; i < nx; ++i) {
    const double h = 1e-6;
    Eigen::VectorXd xp = x, xm = x, fp(nx), fm(nx);
    xp(i) += h;
    xm(i) -= h;
    multibody::CalcStateDerivative<double>(model, data, 0.0, xp, r, fp);
    multibody::CalcStateDerivative<double>(model, data, 0.0, xm, r, fm);
    const Eigen::VectorXd fd = (fp - fm) / (2 * h);
    EXPECT_LT((J.col(i) - fd).cwiseAbs().maxCoeff(), 1e-5 * (1.0 + fd.norm())) << "column " << i;
  }
}

// The message of the ConfigError building `text` throws (empty if none).
std::string BuildError(const std::string& text) {
  try {
    BuildText(text, "bad.yaml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(ConstraintsTest, AnUnmeetableLoopIsRefusedWithFileLineAndResidual) {
  std::string text = ReadText(kSource + "/examples/models/four_bar.yaml");
  text = std::regex_replace(text, std::regex("l0: \\{value: 0.3,"), "l0: {value: 1.0,");
  const std::string e = BuildError(text);
  EXPECT_NE(e.find("bad.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("constraints[0]"), std::string::npos) << e;
  EXPECT_NE(e.find("loop closure"), std::string::npos) << e;
  EXPECT_NE(e.find("residual"), std::string::npos) << e;
}

const char* kRollingDisc = R"(name: disc
parameters:
  r: {value: 0.5, unit: m}
  c0: 0.5
coordinates:
  - {name: x, unit: m}
  - {name: th, unit: rad}
  - {name: y, unit: m}
speeds:
  - {name: v, unit: m/s}
  - {name: w, unit: rad/s, initial: 2}
  - {name: vy, unit: m/s}
frames:
  - {name: D, parent: N, axis: z, angle: th}
points:
  - {name: C, from: O, frame: N, position: [x, y, 0]}
bodies:
  - {name: disc, frame: D, mass_center: C, mass: 1, inertia: [0.1, 0.1, 0.1]}
constraints:
  - {name: rolling, nonholonomic: CONSTRAINT}
dependent_speeds: [DEPENDENT]
)";

std::string Disc(const std::string& constraint, const std::string& dependent) {
  std::string text = std::regex_replace(kRollingDisc, std::regex("CONSTRAINT"), constraint);
  return std::regex_replace(text, std::regex("DEPENDENT"), dependent);
}

TEST(ConstraintsTest, ANonholonomicExpressionRollsTheDisc) {
  const models::BuiltModel built = BuildText(Disc("v + r * w", "v"), "disc.yaml");
  const multibody::AssembledState a =
      multibody::AssembleState(built.model, 0.0, built.model.initial_state());
  EXPECT_NEAR(a.x(3), -1.0, 1e-15);  // v = −r w
}

TEST(ConstraintsTest, ASingularChoiceOfDependentSpeedsIsRefusedAtItsLine) {
  const std::string e = BuildError(Disc("v + r * w", "vy"));
  EXPECT_NE(e.find("bad.yaml:21: dependent_speeds"), std::string::npos) << e;
  EXPECT_NE(e.find("choose other dependent speeds"), std::string::npos) << e;
}

TEST(ConstraintsTest, AConstraintNotLinearInTheSpeedsIsRefusedAtItsLine) {
  const std::string e = BuildError(Disc("\"c0 * v * w + r * w\"", "v"));
  EXPECT_NE(e.find("bad.yaml:20: constraints[0].nonholonomic"), std::string::npos) << e;
  EXPECT_NE(e.find("not linear in the speeds"), std::string::npos) << e;
  const std::string e2 = BuildError(Disc("\"c0 * sin(c0 * v) + w\"", "v"));
  EXPECT_NE(e2.find("not linear in the speeds"), std::string::npos) << e2;
}

TEST(ConstraintsTest, ConstrainedModelsArePrintedWithTheirReducedEquations) {
  // The four-bar: three coordinates and speeds, two closing rows (x and y of the coincident
  // points), so two dependent speeds and one independent; the reduced system is n × n.
  const models::BuiltModel built = FourBar();
  const symbolic::Equations eq = symbolic::DeriveEquations(built.model);
  const int n = static_cast<int>(eq.u.size());
  const std::size_t m = eq.constrained.dependent.size();
  EXPECT_EQ(m, 2u);
  EXPECT_EQ(eq.constrained.independent.size(), std::size_t(n) - m);
  EXPECT_EQ(eq.constrained.rows.size(), m);
  EXPECT_EQ(eq.constrained.M.size(), std::size_t(n));
  EXPECT_EQ(eq.constrained.f.size(), std::size_t(n));
}

}  // namespace
}  // namespace hybridtest
