// examples/models/rotor.yaml equals the built-in C++ rotor (3 blades, default parameters): the
// same M, g, ẋ, slot displacements, coupling matrix and state Jacobian at random states, to
// 1e-13 relative. Two independent writings of the paper's Eqs. (9)–(12).
#include <gtest/gtest.h>

#include <random>

#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/kane.h"
#include "support/multibody_helpers.h"

namespace hybridtest::modelfile {
namespace {

using multibody::Data;

models::BuiltModel RotorFromFile() {
  const ModelFile file = LoadModelFile(HYBRIDTEST_SOURCE_DIR "/examples/models/rotor.yaml");
  return BuildModelFile(file, file.parameters);
}

double RelativeError(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

TEST(RotorFileTest, DeclaresWhatTheBuiltInRotorDeclares) {
  const models::BuiltModel file = RotorFromFile();
  const models::BuiltModel cpp = test_support::DefaultModel("rotor", 3);
  ASSERT_EQ(file.model.num_coordinates(), cpp.model.num_coordinates());
  ASSERT_EQ(file.model.num_slots(), cpp.model.num_slots());
  for (int k = 0; k < cpp.model.num_coordinates(); ++k) {
    EXPECT_EQ(file.model.coordinates()[k].name, cpp.model.coordinates()[k].name);
    EXPECT_EQ(file.model.coordinates()[k].unit, cpp.model.coordinates()[k].unit);
    EXPECT_EQ(file.model.speeds()[k].unit, cpp.model.speeds()[k].unit);
  }
  for (int s = 0; s < cpp.model.num_slots(); ++s) {
    EXPECT_EQ(file.model.slots()[s].info.name, cpp.model.slots()[s].info.name);
    EXPECT_EQ(file.model.slots()[s].info.unit, "N");
    EXPECT_EQ(file.slot_stiffness[s], cpp.slot_stiffness[s]);
  }
  EXPECT_EQ(file.name, "rotor");
  // The file's fields are affine like the C++ ones (the engine's fast path).
  EXPECT_FALSE(file.model.has_general_fields());
}

TEST(RotorFileTest, EquationsOfMotionEqualTheBuiltInRotorAtRandomStates) {
  const models::BuiltModel file = RotorFromFile();
  const models::BuiltModel cpp = test_support::DefaultModel("rotor", 3);
  Data<double> df(file.model), dc(cpp.model);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> time(0.0, 3.0);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::VectorXd x = test_support::RandomState(rng, test_support::CoordinateScales(cpp), 5.0);
    const Eigen::VectorXd r = test_support::RandomForces(rng, 3, 300.0);
    const double t = time(rng);
    Eigen::VectorXd xf(8), xc(8), d_f(3), d_c(3);
    multibody::CalcStateDerivative<double>(file.model, df, t, x, r, xf);
    multibody::CalcStateDerivative<double>(cpp.model, dc, t, x, r, xc);
    EXPECT_LT(RelativeError(df.M, dc.M), 1e-13) << "trial " << trial;
    EXPECT_LT(RelativeError(df.g, dc.g), 1e-13) << "trial " << trial;
    EXPECT_LT(RelativeError(xf, xc), 1e-13) << "trial " << trial;
    multibody::CalcSlotDisplacements<double>(file.model, df, t, x.head(4), d_f);
    multibody::CalcSlotDisplacements<double>(cpp.model, dc, t, x.head(4), d_c);
    EXPECT_LT(RelativeError(d_f, d_c), 1e-15);
    if (trial % 10 == 0) {
      EXPECT_LT(RelativeError(multibody::CalcCouplingMatrix(file.model, t, x),
                              multibody::CalcCouplingMatrix(cpp.model, t, x)), 1e-13);
      EXPECT_LT(RelativeError(multibody::CalcStateJacobian(file.model, t, x, r),
                              multibody::CalcStateJacobian(cpp.model, t, x, r)), 1e-13);
    }
  }
}

TEST(RotorFileTest, ParametersOverrideLikeTheBuiltIn) {
  ModelFile file = LoadModelFile(HYBRIDTEST_SOURCE_DIR "/examples/models/rotor.yaml");
  models::ParameterSet p = file.parameters;
  p.Set("k_b", 5250.0, "test");
  p.Set("m_b", 2.5, "test");
  const models::BuiltModel built = BuildModelFile(file, p);
  models::ParameterSet pc = models::DefaultParameters("rotor", 3);
  pc.Set("k_b", 5250.0, "test");
  pc.Set("m_b", 2.5, "test");
  const models::BuiltModel cpp = models::BuildModel("rotor", 3, pc);
  EXPECT_EQ(built.slot_stiffness[0], 5250.0);
  std::mt19937 rng(3);
  const Eigen::VectorXd x = test_support::RandomState(rng, test_support::CoordinateScales(cpp), 5.0);
  const Eigen::VectorXd r = test_support::RandomForces(rng, 3, 300.0);
  EXPECT_LT(RelativeError(test_support::StateDerivative(built.model, 0.7, x, r),
                          test_support::StateDerivative(cpp.model, 0.7, x, r)), 1e-13);
}

}  // namespace
}  // namespace hybridtest::modelfile
