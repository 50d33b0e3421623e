// The hand-written closed form of the rotor (bench/rotor_closed_form.h), the benchmark's
// reference, must be the same function as the Kane engine's rotor: M, g and ẋ agree to 1e-12
// (normwise relative, ‖a − b‖∞ ≤ 1e-12 ‖b‖∞) at 100 random states, including large speeds.
//
// The closed form's source is compiled into this test by inclusion (it lives in bench/ and is
// otherwise built only into hybridtest_bench, which may be disabled).
#include <gtest/gtest.h>

#include <random>

#include "../../bench/rotor_closed_form.cc"
#include "../../bench/rotor_closed_form.h"
#include "hybridtest/models/catalogue.h"
#include "hybridtest/multibody/kane.h"

namespace hybridtest::bench {
namespace {

constexpr double kTolerance = 1e-12;

template <typename A, typename B>
double RelativeError(const A& a, const B& b) {
  return (a - b).template lpNorm<Eigen::Infinity>() / b.template lpNorm<Eigen::Infinity>();
}

struct Sample {
  double t;
  RotorState x;
  Eigen::Vector3d r;
};

// Random states: deflections up to ±0.2 m, hub angle over many turns, blade speeds up to
// ±50 m/s and hub speeds up to ±300 rad/s (the centrifugal terms dominate there), t in [0, 3] s
// (through the ramp), restoring forces up to ±2 kN.
std::vector<Sample> RandomSamples(int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Sample> samples;
  for (int k = 0; k < count; ++k) {
    Sample s;
    s.t = 1.5 * (1.0 + unit(rng));
    for (int i = 0; i < 3; ++i) s.x(i) = 0.2 * unit(rng);
    s.x(3) = 50.0 * unit(rng);
    for (int i = 0; i < 3; ++i) s.x(4 + i) = 50.0 * unit(rng);
    s.x(7) = (k % 4 == 0 ? 300.0 : 10.0) * unit(rng);
    for (int i = 0; i < 3; ++i) s.r(i) = 2000.0 * unit(rng);
    samples.push_back(s);
  }
  return samples;
}

class RotorClosedFormTest : public ::testing::Test {
 protected:
  RotorClosedFormTest()
      : built_(models::BuildModel("rotor", 3, models::DefaultParameters("rotor", 3))),
        data_(built_.model) {}
  models::BuiltModel built_;
  multibody::Data<double> data_;
  RotorParameters p_;
};

TEST_F(RotorClosedFormTest, MassMatrixForcingAndRhsMatchTheEngine) {
  double worst_M = 0.0, worst_g = 0.0, worst_xdot = 0.0;
  for (const Sample& s : RandomSamples(100, 20261122)) {
    Eigen::VectorXd xdot_engine(8);
    multibody::CalcStateDerivative<double>(built_.model, data_, s.t, Eigen::VectorXd(s.x),
                                           Eigen::VectorXd(s.r), xdot_engine);
    Eigen::Matrix4d M;
    Eigen::Vector4d g;
    RotorState xdot;
    CalcRotorMassMatrix(p_, s.x, M);
    CalcRotorForcing(p_, s.t, s.x, s.r, g);
    CalcRotorRhs(p_, s.t, s.x, s.r, xdot);
    const double eM = RelativeError(M, data_.M);
    const double eg = RelativeError(g, data_.g);
    const double ex = RelativeError(xdot, xdot_engine);
    EXPECT_LE(eM, kTolerance) << "t = " << s.t << ", x = " << s.x.transpose();
    EXPECT_LE(eg, kTolerance) << "t = " << s.t << ", x = " << s.x.transpose();
    EXPECT_LE(ex, kTolerance) << "t = " << s.t << ", x = " << s.x.transpose();
    worst_M = std::max(worst_M, eM);
    worst_g = std::max(worst_g, eg);
    worst_xdot = std::max(worst_xdot, ex);
  }
  RecordProperty("worst_relative_error_xdot", std::to_string(worst_xdot));
  std::printf("worst normwise relative error: M %.2e, g %.2e, xdot %.2e\n", worst_M, worst_g,
              worst_xdot);
}

TEST_F(RotorClosedFormTest, ArrowSolveMatchesCholesky) {
  for (const Sample& s : RandomSamples(100, 7)) {
    RotorState a, b;
    CalcRotorRhs(p_, s.t, s.x, s.r, a);
    CalcRotorRhsArrow(p_, s.t, s.x, s.r, b);
    EXPECT_LE(RelativeError(b, a), kTolerance) << "t = " << s.t << ", x = " << s.x.transpose();
  }
}

// The comparison can fail: a wrong sign in one term (here the Coriolis term of g_4, as a
// transcription of the paper's Eq. (20) might have it) is far outside the tolerance.
TEST_F(RotorClosedFormTest, ToleranceDetectsASignError) {
  const Sample s = RandomSamples(1, 3).front();
  Eigen::VectorXd xdot_engine(8);
  multibody::CalcStateDerivative<double>(built_.model, data_, s.t, Eigen::VectorXd(s.x),
                                         Eigen::VectorXd(s.r), xdot_engine);
  Eigen::Vector4d g;
  CalcRotorForcing(p_, s.t, s.x, s.r, g);
  double coriolis = 0.0;
  for (int i = 0; i < 3; ++i) coriolis += 2.0 * s.x(i) * p_.m_b * s.x(4 + i) * s.x(7);
  g(3) += 2.0 * coriolis;  // flips the sign of the Coriolis term
  EXPECT_GT(RelativeError(g, data_.g), 1e3 * kTolerance);
}

}  // namespace
}  // namespace hybridtest::bench
