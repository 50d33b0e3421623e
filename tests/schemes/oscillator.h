#pragma once
// Test fixtures for the hybrid schemes: a damped, forced linear oscillator m q̈ + c q̇ + r = f(t)
// whose restoring force r comes from a "specimen" (a numerical spring r = k d behind the
// seam), and a seam that counts and records every trial.
#include <Eigen/Core>

#include <cmath>
#include <vector>

#include "hybridtest/multibody/model.h"
#include "hybridtest/schemes/hybrid_scheme.h"

namespace hybridtest::schemes::testing {

struct Oscillator {
  double m = 2.0;      // [kg]
  double c = 0.6;      // [N·s/m]
  double k = 800.0;    // [N/m] specimen stiffness
  double f0 = 5.0;     // [N] forcing amplitude
  double w = 7.0;      // [rad/s] forcing frequency
};

inline multibody::Model OscillatorModel(const Oscillator& o) {
  using multibody::ScalarField;
  multibody::ModelBuilder b({{"q1", "m", "displacement"}});
  const auto P = b.AddPoint("P", b.origin(), b.newtonian(), {ScalarField::Coordinate(0), {}, {}});
  b.AddParticle("mass", P, o.m);
  b.AddRestoringForceSlot("r1", "spring", ScalarField::Coordinate(0));
  const double c = o.c, f0 = o.f0, w = o.w;
  b.AddForce("spring, damper, forcing", P, b.newtonian(), [=](const auto& a) {
    using T = std::decay_t<decltype(a.u[0])>;
    return multibody::Vector3<T>(-a.r[0] - c * a.u[0] + f0 * sin(w * a.t), T(0.0), T(0.0));
  });
  return std::move(b).Build();
}

// A linear (or cubic) spring behind the seam; records every trial.
class SpringSeam final : public SubstructureSeam {
 public:
  explicit SpringSeam(double k, double cubic = 0.0) : k_(k), cubic_(cubic) {}
  void Trial(const TrialPoint& at, const Eigen::VectorXd& slot_d,
             Eigen::Ref<Eigen::VectorXd> r) override {
    const double d = slot_d(0);
    r(0) = k_ * d * (1.0 + cubic_ * d * d);
    trials.push_back({at.step, at.stage, at.t, d});
  }
  struct Record {
    long step;
    int stage;
    double t;
    double d;
  };
  std::vector<Record> trials;

 private:
  double k_, cubic_;
};

class CollectRows final : public RowSink {
 public:
  void Row(double t, const Eigen::VectorXd& x, const Eigen::VectorXd&) override {
    times.push_back(t);
    q.push_back(x(0));
  }
  std::vector<double> times, q;
};

}  // namespace hybridtest::schemes::testing
