// The built-in models' parameters: overrides (all-blades and per-blade precedence), errors that
// name the parameter, N = 1 blade, and the default azimuths ψ_i = 2π(i−1)/N.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "hybridtest/common/error.h"
#include "hybridtest/models/catalogue.h"
#include "hybridtest/multibody/kane.h"

namespace hybridtest::models {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

template <class F>
std::string ConfigErrorOf(F&& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a ConfigError";
  return "";
}

// Mass matrix at the zero state.
Eigen::MatrixXd MassMatrix(const BuiltModel& built) {
  multibody::Data<double> data(built.model);
  multibody::CalcKinematics<double>(built.model, data, 0.0,
                                    Eigen::VectorXd::Zero(built.model.num_states()));
  multibody::CalcMassMatrix<double>(built.model, data);
  return data.M;
}

TEST(RotorParametersTest, PerBladeOverrideTakesPrecedenceOverAllBlades) {
  ParameterSet p = DefaultParameters("rotor", 3);
  p.Set("k_b", 5000.0, "test");
  p.Set("blade2.k_b", 3000.0, "test");
  p.Set("m_b", 2.0, "test");
  p.Set("blade3.m_b", 4.0, "test");
  const BuiltModel rotor = BuildModel("rotor", 3, p);
  EXPECT_EQ(rotor.slot_stiffness, (std::vector<double>{5000.0, 3000.0, 5000.0}));
  const Eigen::MatrixXd M = MassMatrix(rotor);
  EXPECT_DOUBLE_EQ(M(0, 0), 2.0);
  EXPECT_DOUBLE_EQ(M(1, 1), 2.0);
  EXPECT_DOUBLE_EQ(M(2, 2), 4.0);
  EXPECT_DOUBLE_EQ(M(2, 3), 4.0 * 0.5);  // m_b l_b
  // The resolved set records the per-blade values.
  EXPECT_DOUBLE_EQ(rotor.parameters.Get("blade1.k_b"), 5000.0);
  EXPECT_DOUBLE_EQ(rotor.parameters.Get("blade2.k_b"), 3000.0);
  EXPECT_DOUBLE_EQ(rotor.parameters.Get("blade3.m_b"), 4.0);
}

TEST(RotorParametersTest, UnknownParameterListsTheKnownOnes) {
  ParameterSet p = DefaultParameters("rotor", 2);
  EXPECT_THAT(ConfigErrorOf([&] { p.Set("k_blade", 1.0, "cfg.yaml:7: model.parameters.k_blade"); }),
              AllOf(HasSubstr("cfg.yaml:7: model.parameters.k_blade"), HasSubstr("'k_blade'"),
                    HasSubstr("k_b"), HasSubstr("blade2.psi"), HasSubstr("I_g")));
  EXPECT_THAT(ConfigErrorOf([&] { p.Set("blade3.k_b", 1.0, "here"); }), HasSubstr("blade3.k_b"));
  EXPECT_THAT(ConfigErrorOf([&] { p.Set("k_b", std::nan(""), "here"); }), HasSubstr("finite"));
}

TEST(RotorParametersTest, NonPositiveMassIsRejectedNamingTheParameter) {
  {
    ParameterSet p = DefaultParameters("rotor", 3);
    p.Set("blade2.m_b", -1.0, "test");
    EXPECT_THAT(ConfigErrorOf([&] { BuildModel("rotor", 3, p); }),
                AllOf(HasSubstr("model.parameters.blade2.m_b = -1"), HasSubstr("kg")));
  }
  {
    // An all-blades value is reported through the first blade that inherits it.
    ParameterSet p = DefaultParameters("rotor", 3);
    p.Set("m_b", 0.0, "test");
    EXPECT_THAT(ConfigErrorOf([&] { BuildModel("rotor", 3, p); }),
                AllOf(HasSubstr("m_b = 0"), HasSubstr("positive")));
  }
  {
    ParameterSet p = DefaultParameters("rotor", 3);
    p.Set("I_g", -0.1, "test");
    EXPECT_THAT(ConfigErrorOf([&] { BuildModel("rotor", 3, p); }), HasSubstr("model.parameters.I_g"));
  }
  {
    ParameterSet p = DefaultParameters("double_pendulum", 0);
    p.Set("m2", 0.0, "test");
    EXPECT_THAT(ConfigErrorOf([&] { BuildModel("double_pendulum", 0, p); }),
                HasSubstr("model.parameters.m2 = 0"));
  }
  {
    ParameterSet p = DefaultParameters("spinning_top", 0);
    p.Set("m", -3.0, "test");
    EXPECT_THAT(ConfigErrorOf([&] { BuildModel("spinning_top", 0, p); }),
                HasSubstr("model.parameters.m = -3"));
    ParameterSet q = DefaultParameters("spinning_top", 0);
    q.Set("Ixy", 0.5, "test");  // makes the inertia matrix indefinite
    EXPECT_THAT(ConfigErrorOf([&] { BuildModel("spinning_top", 0, q); }),
                HasSubstr("positive definite"));
  }
}

TEST(RotorParametersTest, UnknownModelAndZeroBladesAreRejected) {
  EXPECT_THAT(ConfigErrorOf([] { DefaultParameters("windmill", 3); }),
              AllOf(HasSubstr("'windmill'"), HasSubstr("rotor"), HasSubstr("double_pendulum"),
                    HasSubstr("spinning_top")));
  EXPECT_THAT(ConfigErrorOf([] { DefaultParameters("rotor", 0); }), HasSubstr("model.blades = 0"));
}

TEST(RotorParametersTest, OneBladeRotorWorks) {
  const BuiltModel rotor = BuildModel("rotor", 1, DefaultParameters("rotor", 1));
  ASSERT_EQ(rotor.model.num_coordinates(), 2);
  ASSERT_EQ(rotor.model.num_slots(), 1);
  multibody::Data<double> data(rotor.model);
  Eigen::Vector4d x(0.03, 0.4, -0.2, 1.1);
  Eigen::VectorXd xdot(4);
  multibody::CalcStateDerivative<double>(rotor.model, data, 2.0, x, Eigen::VectorXd::Constant(1, 50.0),
                                         xdot);
  EXPECT_TRUE(xdot.allFinite());
  // Arrow mass matrix with one blade.
  Eigen::Matrix2d M;
  M << 1.96, 1.96 * 0.5, 1.96 * 0.5, 0.1 + 1.96 * (0.25 + 0.03 * 0.03);
  EXPECT_LT((data.M - M).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_DOUBLE_EQ(rotor.parameters.Get("blade1.psi"), 0.0);
}

TEST(RotorParametersTest, DefaultAzimuthsAreEvenlySpaced) {
  for (int N = 1; N <= 5; ++N) {
    const BuiltModel rotor = BuildModel("rotor", N, DefaultParameters("rotor", N));
    multibody::Data<double> data(rotor.model);
    const double q_hub = 0.37;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(rotor.model.num_states());
    x(N) = q_hub;
    multibody::CalcKinematics<double>(rotor.model, data, 0.0, x);
    for (int i = 1; i <= N; ++i) {
      const double psi = 2 * std::numbers::pi * (i - 1) / N;
      EXPECT_NEAR(rotor.parameters.Get("blade" + std::to_string(i) + ".psi"), psi, 1e-15);
      // Tip i at zero deflection sits at l_b (cos, sin)(q_hub + ψ_i).
      int P = -1;
      for (std::size_t k = 0; k < rotor.model.points().size(); ++k)
        if (rotor.model.points()[k].name == "P" + std::to_string(i)) P = static_cast<int>(k);
      ASSERT_GE(P, 0);
      const Eigen::Vector3d expected(0.5 * std::cos(q_hub + psi), 0.5 * std::sin(q_hub + psi), 0);
      EXPECT_LT((data.p_OP[P] - expected).norm(), 1e-14) << "N = " << N << ", blade " << i;
    }
  }
}

}  // namespace
}  // namespace hybridtest::models
