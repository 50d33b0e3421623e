// Natural modes about an operating point. See modes.h.
#include "hybridtest/multibody/modes.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace hybridtest::multibody {

ModeAnalysis CalcModes(const Model& model, double t, const Eigen::VectorXd& x,
                       const std::vector<double>& slot_stiffness) {
  ModeAnalysis out;
  out.x = AssembleState(model, t, x).x;
  out.linearization = LinearizeConstrained(model, t, out.x, slot_stiffness);
  const Eigen::EigenSolver<Eigen::MatrixXd> solver(out.linearization.A, true);
  const Eigen::VectorXcd lambda = solver.eigenvalues();
  const Eigen::MatrixXcd vectors = solver.eigenvectors();
  for (Eigen::Index i = 0; i < lambda.size(); ++i) {
    Mode mode;
    mode.eigenvalue = lambda(i);
    const double magnitude = std::abs(lambda(i));
    mode.frequency_hz = magnitude / (2.0 * std::numbers::pi);
    mode.damped_frequency_hz = std::abs(lambda(i).imag()) / (2.0 * std::numbers::pi);
    mode.damping_ratio = magnitude > 0.0 ? -lambda(i).real() / magnitude : 0.0;
    mode.shape = vectors.col(i);
    Eigen::Index largest = 0;
    mode.shape.cwiseAbs().maxCoeff(&largest);
    if (std::abs(mode.shape(largest)) > 0.0) mode.shape /= mode.shape(largest);
    out.modes.push_back(std::move(mode));
  }
  std::stable_sort(out.modes.begin(), out.modes.end(), [](const Mode& a, const Mode& b) {
    const double ma = std::abs(a.eigenvalue), mb = std::abs(b.eigenvalue);
    if (ma != mb) return ma < mb;
    return a.eigenvalue.imag() > b.eigenvalue.imag();
  });
  return out;
}

}  // namespace hybridtest::multibody
