// Natural modes about an operating point. See modes.h.
#include "hybridtest/multibody/modes.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace hybridtest::multibody {

ModeAnalysis CalcModes(const Model& model, double t, const Eigen::VectorXd& x,
                       const std::vector<double>& slot_stiffness) {
  ModeAnalysis out;
  out.x = AssembleState(model, t, x).x;
  out.linearization = LinearizeConstrained(model, t, out.x, slot_stiffness);
  const Eigen::MatrixXd& A = out.linearization.A;
  const Eigen::EigenSolver<Eigen::MatrixXd> solver(A, true);
  Eigen::VectorXcd lambda = solver.eigenvalues();
  const Eigen::MatrixXcd vectors = solver.eigenvectors();
  // States that nothing depends on (a zero column: an ignorable coordinate, a wheel angle) are
  // exact zero eigenvalues; removing them, repeatedly, leaves a block with the other
  // eigenvalues (A is block-triangular). Its eigenvalues are more accurate than those of the
  // whole matrix, whose cluster of defective zeros perturbs small ones (the bicycle's capsize
  // mode near its critical speed): they replace the nearest of the whole matrix's.
  std::vector<int> kept(static_cast<std::size_t>(A.rows()));
  for (int i = 0; i < A.rows(); ++i) kept[static_cast<std::size_t>(i)] = i;
  const double scale = A.cwiseAbs().maxCoeff();
  for (bool removed = true; removed && !kept.empty();) {
    removed = false;
    for (std::size_t c = 0; c < kept.size(); ++c) {
      double column = 0.0;
      for (int r : kept) column = std::max(column, std::abs(A(r, kept[c])));
      if (column <= 1e-14 * scale) {
        kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(c));
        removed = true;
        break;
      }
    }
  }
  if (!kept.empty() && kept.size() < static_cast<std::size_t>(A.rows())) {
    Eigen::MatrixXd block(kept.size(), kept.size());
    for (std::size_t i = 0; i < kept.size(); ++i)
      for (std::size_t k = 0; k < kept.size(); ++k) block(i, k) = A(kept[i], kept[k]);
    std::vector<std::complex<double>> exact(A.rows() - kept.size(), 0.0);
    const Eigen::VectorXcd inner = Eigen::EigenSolver<Eigen::MatrixXd>(block, false).eigenvalues();
    for (Eigen::Index i = 0; i < inner.size(); ++i) exact.push_back(inner(i));
    std::vector<bool> used(exact.size(), false);
    for (Eigen::Index i = 0; i < lambda.size(); ++i) {
      std::size_t best = 0;
      double distance = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k < exact.size(); ++k) {
        if (!used[k] && std::abs(exact[k] - lambda(i)) < distance) {
          distance = std::abs(exact[k] - lambda(i));
          best = k;
        }
      }
      used[best] = true;
      lambda(i) = exact[best];
    }
  }
  for (Eigen::Index i = 0; i < lambda.size(); ++i) {
    Mode mode;
    mode.eigenvalue = lambda(i);
    const double magnitude = std::abs(lambda(i));
    mode.frequency_hz = magnitude / (2.0 * std::numbers::pi);
    mode.damped_frequency_hz = std::abs(lambda(i).imag()) / (2.0 * std::numbers::pi);
    mode.damping_ratio = magnitude > 0.0 ? -lambda(i).real() / magnitude : 0.0;
    if (mode.damping_ratio == 0.0) mode.damping_ratio = 0.0;  // +0, not −0, for Re λ = 0
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
