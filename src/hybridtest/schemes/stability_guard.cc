// See stability_guard.h.
#include "hybridtest/schemes/stability_guard.h"

#include <algorithm>
#include <cmath>

#include "hybridtest/multibody/kane.h"
#include "hybridtest/schemes/hybrid_scheme.h"
#include "hybridtest/schemes/step_control.h"

namespace hybridtest::schemes {

StabilityGuard::StabilityGuard(int num_coordinates, int num_slots, double constant)
    : n_(num_coordinates),
      m_(num_slots),
      constant_(constant),
      eigen_(2 * num_coordinates),
      lu_(2 * num_coordinates) {
  for (Eigen::VectorXd* v : {&d_last_, &r_last_, &s_dd_, &s_dr_, &s_rr_, &n_eff_, &r_scratch_,
                             &d_plus_, &d_minus_}) {
    v->setZero(m_);
  }
  for (Eigen::VectorXd* v : {&x_scratch_, &xdot_plus_, &xdot_minus_}) v->setZero(2 * n_);
  lambda_.setZero(2 * n_);
  Q_.setZero(2 * n_, m_);
  R_.setZero(m_, 2 * n_);
  A_.setZero(2 * n_, 2 * n_);
  Jr_.setZero(2 * n_, m_);
  Dx_.setZero(m_, 2 * n_);
}

void StabilityGuard::AddSample(const Eigen::VectorXd& d, const Eigen::VectorXd& r) {
  if (samples_ > 0) {
    for (int s = 0; s < m_; ++s) {
      const double dd = d(s) - d_last_(s);
      const double dr = r(s) - r_last_(s);
      if (!std::isfinite(dd) || !std::isfinite(dr)) continue;
      s_dd_(s) = kForgetting * s_dd_(s) + dd * dd;
      s_dr_(s) = kForgetting * s_dr_(s) + dd * dr;
      s_rr_(s) = kForgetting * s_rr_(s) + dr * dr;
      n_eff_(s) = kForgetting * n_eff_(s) + 1.0;
    }
  }
  d_last_ = d;
  r_last_ = r;
  ++samples_;
}

double StabilityGuard::tangent_stiffness(int s) const {
  if (samples_ < 4 || !(s_dd_(s) > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return s_dr_(s) / s_dd_(s);
}

double StabilityGuard::tangent_stiffness_error(int s) const {
  const double k = tangent_stiffness(s);
  if (!std::isfinite(k) || !(n_eff_(s) > 1.0)) return std::numeric_limits<double>::infinity();
  const double sse = std::max(0.0, s_rr_(s) - k * s_dr_(s));
  return std::sqrt(sse / ((n_eff_(s) - 1.0) * s_dd_(s)));
}

void StabilityGuard::AddErrorEstimate(double e, double h, double tolerance) {
  for (int i = 2; i > 0; --i) {
    e_[i] = e_[i - 1];
    h_[i] = h_[i - 1];
  }
  e_[0] = std::abs(e);
  h_[0] = h;
  errors_ = std::min(errors_ + 1, 3);
  // Grown twice by more than kGrowth, above twice the tolerance, while the step did not grow.
  oscillating_ = errors_ >= 3 && e_[2] > 2.0 * tolerance && h_[0] <= h_[1] && h_[1] <= h_[2] &&
                 e_[0] > kGrowth * e_[1] && e_[1] > kGrowth * e_[2];
}

void StabilityGuard::UpdateModes(const multibody::Model& model, multibody::Data<double>& data,
                                 double t, const Eigen::VectorXd& x, const Eigen::VectorXd& r,
                                 const Eigen::VectorXd& k0) {
  const Eigen::Index nx = 2 * n_;
  // ∂ẋ/∂x at fixed r and ∂d/∂x (zero for the speeds), by central differences.
  x_scratch_ = x;
  Dx_.setZero();
  for (Eigen::Index j = 0; j < nx; ++j) {
    const double step = 1e-6 * std::max(1.0, std::abs(x(j)));
    x_scratch_(j) = x(j) + step;
    multibody::CalcStateDerivative<double>(model, data, t, x_scratch_, r, xdot_plus_);
    if (j < n_) multibody::CalcSlotDisplacements<double>(model, data, t, x_scratch_.head(n_), d_plus_);
    x_scratch_(j) = x(j) - step;
    multibody::CalcStateDerivative<double>(model, data, t, x_scratch_, r, xdot_minus_);
    if (j < n_) multibody::CalcSlotDisplacements<double>(model, data, t, x_scratch_.head(n_), d_minus_);
    x_scratch_(j) = x(j);
    A_.col(j) = (xdot_plus_ - xdot_minus_) / (2.0 * step);
    if (j < n_) Dx_.col(j) = (d_plus_ - d_minus_) / (2.0 * step);
  }
  // ∂ẋ/∂r: the model is linear in r, so a difference is exact to rounding.
  multibody::CalcStateDerivative<double>(model, data, t, x, r, xdot_minus_);
  for (int s = 0; s < m_; ++s) {
    const double delta = 1.0 + std::abs(r(s));
    r_scratch_ = r;
    r_scratch_(s) += delta;
    multibody::CalcStateDerivative<double>(model, data, t, x, r_scratch_, xdot_plus_);
    Jr_.col(s) = (xdot_plus_ - xdot_minus_) / delta;
  }
  // The linearised model with K0, its real modes, and the perturbation's factors.
  Q_.noalias() = Jr_ * k0.asDiagonal();
  A_.noalias() += Q_ * Dx_;
  eigen_.compute(A_, true);
  if (eigen_.info() != Eigen::Success) {
    modes_ = false;
    return;
  }
  lambda_ = eigen_.eigenvalues();
  lu_.compute(eigen_.pseudoEigenvectors());
  Q_ = lu_.solve(Jr_);
  R_.noalias() = Dx_ * eigen_.pseudoEigenvectors();
  modes_ = Q_.allFinite() && R_.allFinite();
}

bool StabilityGuard::HasExcess(const Eigen::VectorXd& k0) const {
  for (int s = 0; s < m_; ++s) {
    const double k = tangent_stiffness(s);
    if (std::isfinite(k) && k - k0(s) - 2.0 * tangent_stiffness_error(s) > 0.0) return true;
  }
  return false;
}

double StabilityGuard::StableStep(const Eigen::VectorXd& k0) const {
  if (!modes_) return std::numeric_limits<double>::infinity();
  // ΔK⁺ per slot: the estimate less two standard errors, where it exceeds K0.
  constexpr int kMaxSlots = 64;
  double dk[kMaxSlots];
  const int m = std::min(m_, kMaxSlots);
  bool any = false;
  for (int s = 0; s < m; ++s) {
    const double k = tangent_stiffness(s);
    const double excess = std::isfinite(k) ? k - k0(s) - 2.0 * tangent_stiffness_error(s) : 0.0;
    dk[s] = excess > 0.0 ? excess : 0.0;
    any = any || dk[s] > 0.0;
  }
  if (!any) return std::numeric_limits<double>::infinity();
  // Per complex pair (columns i, i+1 of V; λ = a + ib): the 2 × 2 block E of V⁻¹ P V with
  // P = ∂ẋ/∂r diag(ΔK⁺) ∂d/∂x; dλ = (E11 + E22)/2 + i (E12 − E21)/2; ω_Δ² = −Re(2 λ dλ).
  double omega2 = 0.0;
  const Eigen::Index nx = lambda_.size();
  for (Eigen::Index i = 0; i + 1 < nx; ++i) {
    const double a = lambda_(i).real(), b = lambda_(i).imag();
    if (b == 0.0) continue;
    if (std::abs(b) > std::abs(a)) {
      double e11 = 0.0, e12 = 0.0, e21 = 0.0, e22 = 0.0;
      for (int s = 0; s < m; ++s) {
        e11 += Q_(i, s) * dk[s] * R_(s, i);
        e12 += Q_(i, s) * dk[s] * R_(s, i + 1);
        e21 += Q_(i + 1, s) * dk[s] * R_(s, i);
        e22 += Q_(i + 1, s) * dk[s] * R_(s, i + 1);
      }
      const double p = 0.5 * (e11 + e22), q = 0.5 * (e12 - e21);
      omega2 = std::max(omega2, 2.0 * (b * q - a * p));
    }
    ++i;  // its conjugate
  }
  if (!(omega2 > 0.0)) return std::numeric_limits<double>::infinity();
  return kStabilityMargin * constant_ / std::sqrt(omega2);
}

double StabilityGuard::Limit(double h_next, double h, double dt_min, const Eigen::VectorXd& k0) {
  double limit = StableStep(k0);
  if (oscillating_) {
    limit = std::min(limit, 0.5 * h);
    hold_ = kHoldSteps;
  } else if (hold_ > 0) {
    limit = std::min(limit, h);
    --hold_;
  }
  if (!(h_next > limit)) return h_next;
  ++shortened_;
  return std::max(dt_min, limit);
}

nlohmann::json StabilityGuard::SaveState() const {
  return {{"samples", samples_},       {"d_last", ToJson(d_last_)}, {"r_last", ToJson(r_last_)},
          {"s_dd", ToJson(s_dd_)},     {"s_dr", ToJson(s_dr_)},     {"s_rr", ToJson(s_rr_)},
          {"n", ToJson(n_eff_)},           {"e", {e_[0], e_[1], e_[2]}}, {"h", {h_[0], h_[1], h_[2]}}, {"errors", errors_},
          {"hold", hold_},             {"oscillating", oscillating_},
          {"shortened", shortened_}};
}

void StabilityGuard::RestoreState(const nlohmann::json& state) {
  if (state.is_null()) {
    *this = StabilityGuard(n_, m_, constant_);
    return;
  }
  samples_ = state.at("samples").get<int>();
  d_last_ = VectorFromJson(state.at("d_last"), m_, "guard d_last");
  r_last_ = VectorFromJson(state.at("r_last"), m_, "guard r_last");
  s_dd_ = VectorFromJson(state.at("s_dd"), m_, "guard s_dd");
  s_dr_ = VectorFromJson(state.at("s_dr"), m_, "guard s_dr");
  s_rr_ = VectorFromJson(state.at("s_rr"), m_, "guard s_rr");
  n_eff_ = VectorFromJson(state.at("n"), m_, "guard n");
  for (int i = 0; i < 3; ++i) {
    e_[i] = state.at("e").at(i).get<double>();
    h_[i] = state.at("h").at(i).get<double>();
  }
  errors_ = state.at("errors").get<int>();
  hold_ = state.at("hold").get<int>();
  oscillating_ = state.at("oscillating").get<bool>();
  shortened_ = state.at("shortened").get<long>();
  modes_ = false;  // recomputed after the next step
}

}  // namespace hybridtest::schemes
