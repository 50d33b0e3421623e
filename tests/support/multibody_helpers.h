#pragma once
// Small helpers shared by the multibody and models tests: building the built-in models with
// their defaults, random states, and evaluating the right-hand side into fresh vectors.
#include <Eigen/Core>

#include <algorithm>
#include <random>
#include <string>

#include "hybridtest/models/catalogue.h"
#include "hybridtest/multibody/kane.h"

namespace hybridtest::test_support {

// The built-in model `name` with default parameters (the rotor with `blades` blades).
inline models::BuiltModel DefaultModel(const std::string& name, int blades = 3) {
  return models::BuildModel(name, blades, models::DefaultParameters(name, blades));
}

// A reproducible random state x = [q; u] (2n): q_k uniform in ±q_scale[k] (or ±q_default),
// u uniform in ±u_scale.
inline Eigen::VectorXd RandomState(std::mt19937& rng, const Eigen::VectorXd& q_scale,
                                   double u_scale) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Eigen::Index n = q_scale.size();
  Eigen::VectorXd x(2 * n);
  for (Eigen::Index k = 0; k < n; ++k) x(k) = q_scale(k) * unit(rng);
  for (Eigen::Index k = 0; k < n; ++k) x(n + k) = u_scale * unit(rng);
  return x;
}

// Coordinate scales that keep each built-in model away from singular configurations: the
// rotor's tip deflections ±5 cm and hub angle ±π; the pendulum's angles ±π; the top's
// q2 within ±1.2 rad (W is singular at |q2| = π/2).
inline Eigen::VectorXd CoordinateScales(const models::BuiltModel& built) {
  const int n = built.model.num_coordinates();
  Eigen::VectorXd s = Eigen::VectorXd::Constant(n, 3.14159);
  if (built.name == "rotor") s.head(n - 1).setConstant(0.05);
  if (built.name == "spinning_top") s(1) = 1.2;
  return s;
}

// Random restoring forces r (num_slots), uniform in ±scale [N].
inline Eigen::VectorXd RandomForces(std::mt19937& rng, int slots, double scale) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::VectorXd r(slots);
  for (int s = 0; s < slots; ++s) r(s) = scale * unit(rng);
  return r;
}

// ẋ = f_rhs(t, x, r) (2n) with a fresh workspace.
inline Eigen::VectorXd StateDerivative(const multibody::Model& model, double t,
                                       const Eigen::VectorXd& x, const Eigen::VectorXd& r) {
  multibody::Data<double> data(model);
  Eigen::VectorXd xdot(model.num_states());
  multibody::CalcStateDerivative<double>(model, data, t, x, r, xdot);
  return xdot;
}

// Largest absolute entry of a − b, relative to max(1, largest absolute entry of b).
inline double RelativeError(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (b.size() == 0) return a.size() == 0 ? 0.0 : 1.0;
  const double scale = std::max(1.0, b.cwiseAbs().maxCoeff());
  return (a - b).cwiseAbs().maxCoeff() / scale;
}

}  // namespace hybridtest::test_support
