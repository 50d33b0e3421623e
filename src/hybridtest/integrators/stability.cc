// See stability.h.
#include "hybridtest/integrators/stability.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hybridtest::integrators {
namespace {

// |R(hλ)| within the admissible bound at step h (see stability.h).
bool StableAt(const Eigen::VectorXd& beta, std::complex<double> lambda, double h) {
  const double amplification = std::abs(EvalStabilityPolynomial(beta, h * lambda));
  const double exact = std::exp(h * lambda.real());  // |e^{hλ}|
  return amplification <= std::max(1.0, exact) + kNeutralTolerance;
}

}  // namespace

Eigen::VectorXd StabilityPolynomial(const ButcherTableau& tableau) {
  const int s = std::max(0, tableau.stages());  // ≥ 0: beta is never empty
  Eigen::VectorXd beta(s + 1);
  beta(0) = 1.0;
  Eigen::VectorXd power = Eigen::VectorXd::Ones(s);  // a^{k−1} 𝟙
  for (int k = 1; k <= s; ++k) {
    beta(k) = tableau.b.dot(power);
    power = tableau.a * power;
  }
  return beta;
}

std::complex<double> EvalStabilityPolynomial(const Eigen::VectorXd& beta,
                                             std::complex<double> z) {
  std::complex<double> r = 0.0;  // Horner
  for (Eigen::Index k = beta.size() - 1; k >= 0; --k) r = r * z + beta(k);
  return r;
}

double LargestStableStep(const Eigen::VectorXd& beta, std::complex<double> lambda) {
  const double rate = std::abs(lambda);
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  if (!(rate >= kNegligibleRate)) return kInfinity;
  // The stability region of an explicit s-stage method lies within |z| ≤ 2s + 2: scan the ray
  // in steps of |z| = 1e-3 for the first unstable point, then bisect the crossing.
  const double z_max = 2.0 * static_cast<double>(beta.size()) + 2.0;
  constexpr double kScan = 1e-3;
  double stable = 0.0;
  for (double z = kScan; z <= z_max; z += kScan) {
    const double h = z / rate;
    if (StableAt(beta, lambda, h)) {
      stable = h;
      continue;
    }
    double unstable = h;
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (stable + unstable);
      (StableAt(beta, lambda, mid) ? stable : unstable) = mid;
    }
    return stable;
  }
  return kInfinity;  // stable along the whole scanned ray (not for a polynomial R of degree ≥ 1)
}

double LargestStableStep(const ButcherTableau& tableau,
                         const std::vector<std::complex<double>>& eigenvalues,
                         std::complex<double>* limiting) {
  const Eigen::VectorXd beta = StabilityPolynomial(tableau);
  double best = std::numeric_limits<double>::infinity();
  for (const std::complex<double>& lambda : eigenvalues) {
    const double h = LargestStableStep(beta, lambda);
    if (h < best) {
      best = h;
      if (limiting != nullptr) *limiting = lambda;
    }
  }
  return best;
}

}  // namespace hybridtest::integrators
