// Kinematic quantities in Data<T> against their definitions: the spinning top's body angular
// velocity is u (which validates the kinematical matrix W), and velocities, angular velocities
// and remainder accelerations equal finite differences of positions, rotations and velocities
// along the motion with u̇ = 0.
#include <gtest/gtest.h>

#include <random>

#include "hybridtest/multibody/kane.h"
#include "support/multibody_helpers.h"

namespace hybridtest::multibody {
namespace {

using test_support::CoordinateScales;
using test_support::DefaultModel;
using test_support::RandomState;

int FrameIndex(const Model& model, const std::string& name) {
  for (std::size_t i = 0; i < model.frames().size(); ++i)
    if (model.frames()[i].name == name) return static_cast<int>(i);
  ADD_FAILURE() << "no frame " << name;
  return 0;
}
int PointIndex(const Model& model, const std::string& name) {
  for (std::size_t i = 0; i < model.points().size(); ++i)
    if (model.points()[i].name == name) return static_cast<int>(i);
  ADD_FAILURE() << "no point " << name;
  return 0;
}

Eigen::Matrix3d Skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d S;
  S << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return S;
}

// u_i = ω^C · ĉ_i, so R_NCᵀ ω_NC = u at every state.
TEST(KinematicsTest, SpinningTopBodyAngularVelocityIsU) {
  const models::BuiltModel top = DefaultModel("spinning_top");
  const int C = FrameIndex(top.model, "C");
  Data<double> data(top.model);
  std::mt19937 rng(21);
  for (int trial = 0; trial < 30; ++trial) {
    const Eigen::VectorXd x = RandomState(rng, CoordinateScales(top), 10.0);
    CalcKinematics<double>(top.model, data, 0.0, x);
    const Eigen::Vector3d w_C = data.R_NF[C].transpose() * data.w_NF[C];
    EXPECT_LT((w_C - x.tail(3)).norm(), 1e-12 * (1 + x.tail(3).norm())) << trial;
    // Partial angular velocities in C are the unit vectors.
    const Eigen::Matrix3d Wp_C = data.R_NF[C].transpose() * data.w_partial[C];
    EXPECT_LT((Wp_C - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12) << trial;
  }
}

// Along q(s) = q + s q̇ (q̇ = W u), dR_NC/ds = [ω]× R_NC: a check of W independent of the
// definition of u (a wrong W gives a wrong q̇ and breaks this).
TEST(KinematicsTest, SpinningTopRotationRateMatchesAngularVelocity) {
  const models::BuiltModel top = DefaultModel("spinning_top");
  const int C = FrameIndex(top.model, "C");
  const int G = PointIndex(top.model, "G");
  Data<double> data(top.model);
  std::mt19937 rng(22);
  const double h = 1e-6;
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd x = RandomState(rng, CoordinateScales(top), 3.0);
    CalcKinematics<double>(top.model, data, 0.0, x);
    const Eigen::Matrix3d R = data.R_NF[C];
    const Eigen::Vector3d w = data.w_NF[C];
    const Eigen::Vector3d v_G = data.v_NP[G];
    const Eigen::Vector3d qdot = data.qdot;
    auto at = [&](double s) {
      Eigen::VectorXd xs = x;
      xs.head(3) += s * qdot;
      CalcKinematics<double>(top.model, data, 0.0, xs);
      return std::pair{data.R_NF[C], data.p_OP[G]};
    };
    const auto [Rp, pp] = at(h);
    const auto [Rm, pm] = at(-h);
    EXPECT_LT(((Rp - Rm) / (2 * h) - Skew(w) * R).cwiseAbs().maxCoeff(), 1e-7 * (1 + w.norm()))
        << trial;
    EXPECT_LT(((pp - pm) / (2 * h) - v_G).norm(), 1e-7 * (1 + v_G.norm())) << trial;
  }
}

// The rotor's tip velocity equals the time derivative of the tip position along q(s) = q + s u
// (identity kinematics), and the remainder acceleration that of the velocity with u fixed.
TEST(KinematicsTest, RotorTipVelocityAndAccelerationMatchFiniteDifferences) {
  const models::BuiltModel rotor = DefaultModel("rotor");
  Data<double> data(rotor.model);
  std::mt19937 rng(23);
  const double h = 1e-6;
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd x = RandomState(rng, CoordinateScales(rotor), 5.0);
    const Eigen::VectorXd u = x.tail(4);
    CalcKinematics<double>(rotor.model, data, 0.0, x);
    for (int blade = 1; blade <= 3; ++blade) {
      const int P = PointIndex(rotor.model, "P" + std::to_string(blade));
      const Eigen::Vector3d v = data.v_NP[P], a = data.a_rem[P];
      Data<double> dp(rotor.model), dm(rotor.model);
      Eigen::VectorXd xp = x, xm = x;
      xp.head(4) += h * u;
      xm.head(4) -= h * u;
      CalcKinematics<double>(rotor.model, dp, 0.0, xp);
      CalcKinematics<double>(rotor.model, dm, 0.0, xm);
      const double scale = 1 + v.norm() + a.norm();
      EXPECT_LT(((dp.p_OP[P] - dm.p_OP[P]) / (2 * h) - v).norm(), 1e-7 * scale) << trial;
      EXPECT_LT(((dp.v_NP[P] - dm.v_NP[P]) / (2 * h) - a).norm(), 1e-6 * scale) << trial;
      // Partial velocities: v = Σ_j v_j u_j (v is linear in u here).
      EXPECT_LT((data.v_partial[P] * u - v).norm(), 1e-12 * scale) << trial;
    }
  }
}

}  // namespace
}  // namespace hybridtest::multibody
