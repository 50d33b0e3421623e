// See double_pendulum.h.
#include "hybridtest/models/double_pendulum.h"

#include "hybridtest/models/model_checks.h"

namespace hybridtest::models {

using multibody::ScalarField;
using multibody::Vector3;

ParameterSet DoublePendulumDefaultParameters() {
  ParameterSet p;
  p.Add("m1", 1.0, "kg", "mass of the first bob");
  p.Add("m2", 1.0, "kg", "mass of the second bob");
  p.Add("l1", 1.0, "m", "length of the first link");
  p.Add("l2", 1.0, "m", "length of the second link");
  p.Add("g", 9.81, "m/s²", "gravity, along n̂_x");
  return p;
}

BuiltModel BuildDoublePendulum(const ParameterSet& p) {
  for (const char* name : {"m1", "m2", "l1", "l2"}) RequirePositive(p, name);
  RequireNonNegative(p, "g");
  const double m1 = p.Get("m1"), m2 = p.Get("m2"), l1 = p.Get("l1"), l2 = p.Get("l2");
  const double g = p.Get("g");
  multibody::ModelBuilder b({{"q1", "rad", "angle of link 1 from n̂_x"},
                             {"q2", "rad", "angle of link 2 relative to link 1"}},
                            {{"u1", "rad/s", "rate of q1"}, {"u2", "rad/s", "rate of q2"}});
  const auto A = b.AddFrameAboutAxis("A", b.newtonian(), Eigen::Vector3d::UnitZ(),
                                     ScalarField::Coordinate(0));
  const auto B = b.AddFrameAboutAxis("B", A, Eigen::Vector3d::UnitZ(), ScalarField::Coordinate(1));
  const auto P1 = b.AddPoint("P1", b.origin(), A, {ScalarField::Constant(l1), {}, {}});
  const auto P2 = b.AddPoint("P2", P1, B, {ScalarField::Constant(l2), {}, {}});
  b.AddParticle("bob1", P1, m1);
  b.AddParticle("bob2", P2, m2);
  for (auto [point, mass] : {std::pair{P1, m1}, std::pair{P2, m2}}) {
    const double weight = mass * g;
    b.AddForce("gravity", point, b.newtonian(), [=](const auto& a) {
      using T = std::decay_t<decltype(a.t)>;
      return Vector3<T>(T(weight), T(0.0), T(0.0));
    });
  }
  return {"double_pendulum", "planar double pendulum of two point masses", p,
          std::move(b).Build(), {}};
}

}  // namespace hybridtest::models
