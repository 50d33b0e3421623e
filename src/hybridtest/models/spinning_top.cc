// See spinning_top.h.
#include "hybridtest/models/spinning_top.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/models/model_checks.h"

namespace hybridtest::models {

using multibody::ScalarField;
using multibody::Vector3;

ParameterSet SpinningTopDefaultParameters() {
  ParameterSet p;
  p.Add("m", 1.0, "kg", "mass");
  p.Add("cx", 0.02, "m", "mass centre, body x");
  p.Add("cy", -0.01, "m", "mass centre, body y");
  p.Add("cz", 0.1, "m", "mass centre, body z");
  p.Add("Ixx", 0.012, "kg·m²", "inertia matrix entry xx about the mass centre");
  p.Add("Iyy", 0.010, "kg·m²", "inertia matrix entry yy about the mass centre");
  p.Add("Izz", 0.006, "kg·m²", "inertia matrix entry zz about the mass centre");
  p.Add("Ixy", 0.001, "kg·m²", "inertia matrix entry xy about the mass centre");
  p.Add("Ixz", -0.0008, "kg·m²", "inertia matrix entry xz about the mass centre");
  p.Add("Iyz", 0.0005, "kg·m²", "inertia matrix entry yz about the mass centre");
  p.Add("g", 9.81, "m/s²", "gravity, along −n̂_z");
  return p;
}

BuiltModel BuildSpinningTop(const ParameterSet& p) {
  RequirePositive(p, "m");
  RequireNonNegative(p, "g");
  const double m = p.Get("m"), g = p.Get("g");
  Eigen::Matrix3d I;
  I << p.Get("Ixx"), p.Get("Ixy"), p.Get("Ixz"),  //
      p.Get("Ixy"), p.Get("Iyy"), p.Get("Iyz"),   //
      p.Get("Ixz"), p.Get("Iyz"), p.Get("Izz");
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(I);
  if (!(eig.eigenvalues().minCoeff() > 0.0)) {
    throw ConfigError(fmt::format("model.parameters Ixx..Iyz: the inertia matrix must be positive "
                                  "definite; its smallest principal moment is {} kg·m²",
                                  eig.eigenvalues().minCoeff()));
  }
  multibody::ModelBuilder b({{"q1", "rad", "rotation about n̂_x"},
                             {"q2", "rad", "rotation about â_y"},
                             {"q3", "rad", "rotation about b̂_z"}},
                            {{"u1", "rad/s", "angular velocity, body x"},
                             {"u2", "rad/s", "angular velocity, body y"},
                             {"u3", "rad/s", "angular velocity, body z"}});
  const auto A = b.AddFrameAboutAxis("A", b.newtonian(), Eigen::Vector3d::UnitX(),
                                     ScalarField::Coordinate(0));
  const auto Bp = b.AddFrameAboutAxis("Bp", A, Eigen::Vector3d::UnitY(), ScalarField::Coordinate(1));
  const auto C = b.AddFrameAboutAxis("C", Bp, Eigen::Vector3d::UnitZ(), ScalarField::Coordinate(2));
  const auto G = b.AddPoint("G", b.origin(), C,
                            {ScalarField::Constant(p.Get("cx")), ScalarField::Constant(p.Get("cy")),
                             ScalarField::Constant(p.Get("cz"))});
  b.AddRigidBody("top", C, G, m, I);
  b.AddForce("gravity", G, b.newtonian(), [=](const auto& a) {
    using T = std::decay_t<decltype(a.t)>;
    return Vector3<T>(T(0.0), T(0.0), T(-m * g));
  });
  b.SetKinematicalEquations(BodyXyzKinematics{});
  return {"spinning_top", "3D rigid body with a full inertia dyadic about a fixed pivot", p,
          std::move(b).Build(), {}};
}

}  // namespace hybridtest::models
