// A frame given by one direction-cosine matrix equals the same rotation built from chained
// axis-angle frames: the spinning top of spinning_top.h with C = N · R_x(q1) R_y(q2) R_z(q3) as
// a single AddFrameWithDcm, against the built-in top (three AddFrameAboutAxis).
#include <gtest/gtest.h>

#include <array>
#include <random>

#include "hybridtest/models/spinning_top.h"
#include "hybridtest/multibody/kane.h"
#include "support/multibody_helpers.h"

namespace hybridtest::multibody {
namespace {

using test_support::RelativeError;

// 3×3 product of row-major jet matrices.
template <class J>
std::array<J, 9> Multiply(const std::array<J, 9>& a, const std::array<J, 9>& b) {
  std::array<J, 9> c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      J s(0.0);
      for (int k = 0; k < 3; ++k) s = s + a[i * 3 + k] * b[k * 3 + j];
      c[i * 3 + j] = s;
    }
  return c;
}

// The built-in top's physics with C given by one DCM.
Model BuildTopWithDcm(const models::ParameterSet& p) {
  const double m = p.Get("m"), g = p.Get("g");
  Eigen::Matrix3d I;
  I << p.Get("Ixx"), p.Get("Ixy"), p.Get("Ixz"), p.Get("Ixy"), p.Get("Iyy"), p.Get("Iyz"),
      p.Get("Ixz"), p.Get("Iyz"), p.Get("Izz");
  ModelBuilder b({{"q1", "rad", ""}, {"q2", "rad", ""}, {"q3", "rad", ""}});
  const FrameId C = b.AddFrameWithDcm("C", b.newtonian(), DcmFunction([](const auto& a, auto out) {
    using J = std::decay_t<decltype(a.t)>;
    const J c1 = cos(a.q[0]), s1 = sin(a.q[0]);
    const J c2 = cos(a.q[1]), s2 = sin(a.q[1]);
    const J c3 = cos(a.q[2]), s3 = sin(a.q[2]);
    const J o(1.0), z(0.0);
    const std::array<J, 9> rx = {o, z, z, z, c1, -s1, z, s1, c1};
    const std::array<J, 9> ry = {c2, z, s2, z, o, z, -s2, z, c2};
    const std::array<J, 9> rz = {c3, -s3, z, s3, c3, z, z, z, o};
    const std::array<J, 9> r = Multiply(Multiply(rx, ry), rz);
    for (int k = 0; k < 9; ++k) out[k] = r[k];
  }));
  const PointId G = b.AddPoint("G", b.origin(), C,
                               {ScalarField::Constant(p.Get("cx")), ScalarField::Constant(p.Get("cy")),
                                ScalarField::Constant(p.Get("cz"))});
  b.AddRigidBody("top", C, G, m, I);
  b.AddForce("gravity", G, b.newtonian(), [=](const auto& a) {
    using T = std::decay_t<decltype(a.t)>;
    return Vector3<T>(T(0.0), T(0.0), T(-m * g));
  });
  b.SetKinematicalEquations(models::BodyXyzKinematics{});  // same W: only the frame differs
  return std::move(b).Build();
}

TEST(DcmFrameTest, SingleDcmFrameEqualsChainedAxisAngleFrames) {
  const models::BuiltModel top = test_support::DefaultModel("spinning_top");
  const Model dcm = BuildTopWithDcm(top.parameters);
  std::mt19937 rng(5);
  Data<double> d_chain(top.model), d_dcm(dcm);
  const Eigen::VectorXd r(0);
  for (int trial = 0; trial < 30; ++trial) {
    const Eigen::VectorXd x =
        test_support::RandomState(rng, test_support::CoordinateScales(top), trial < 15 ? 1.0 : 20.0);
    Eigen::VectorXd x_chain(6), x_dcm(6);
    CalcStateDerivative<double>(top.model, d_chain, 0.0, x, r, x_chain);
    CalcStateDerivative<double>(dcm, d_dcm, 0.0, x, r, x_dcm);
    // Frame C is the last frame of both models.
    const int c_chain = static_cast<int>(top.model.frames().size()) - 1;
    const int c_dcm = static_cast<int>(dcm.frames().size()) - 1;
    EXPECT_LT(RelativeError(d_dcm.R_NF[c_dcm], d_chain.R_NF[c_chain]), 1e-14) << trial;
    EXPECT_LT(RelativeError(d_dcm.w_NF[c_dcm], d_chain.w_NF[c_chain]), 1e-12) << trial;
    EXPECT_LT(RelativeError(d_dcm.alpha_rem[c_dcm], d_chain.alpha_rem[c_chain]), 1e-12) << trial;
    EXPECT_LT(RelativeError(d_dcm.M, d_chain.M), 1e-12) << trial;
    EXPECT_LT(RelativeError(d_dcm.g, d_chain.g), 1e-12) << trial;
    EXPECT_LT(RelativeError(x_dcm, x_chain), 1e-12) << trial;
  }
}

}  // namespace
}  // namespace hybridtest::multibody
