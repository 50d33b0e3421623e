// See alpha_os.h.
#include "hybridtest/schemes/alpha_os.h"

#include <fmt/core.h>

#include <cmath>
#include <limits>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/schemes/step_control.h"

namespace hybridtest::schemes {

AlphaOs::AlphaOs(const multibody::Model& model, const SchemeConfig& config, const SlotInfo& slots,
                 double dt, double duration, long steps)
    : OperatorSplittingScheme(model, config, slots, dt, duration, steps,
                              kAlphaOsStabilityConstant),
      alpha_(config.alpha),
      beta_((1.0 - config.alpha) * (1.0 - config.alpha) / 4.0),
      gamma_(0.5 - config.alpha),
      nv_(model.num_coordinates() + model.num_extra_states()),
      D_(model.num_slots(), model.num_coordinates()),
      jac_(nv_, nv_),
      J_(model.num_states(), model.num_states()),
      B_(model.num_coordinates(), model.num_slots()),
      dfdr_(model.num_coordinates(), model.num_slots()),
      derivatives_(model),
      mass_llt_(model.num_coordinates()),
      newton_lu_(nv_) {
  if (!model.has_identity_kinematics()) {
    throw ConfigError("integrator.scheme = alpha-os: this model has kinematical equations "
                      "q̇ = W(q) u with W ≠ I; α-OS needs q̇ = u. Use scheme: mr-os or "
                      "runge-kutta");
  }
  for (Eigen::VectorXd* v : {&a_, &f_n_, &a_new_, &f_try_, &res_, &delta_}) v->setZero(nv_);
  q_scratch_.setZero(n_);
  a_step_.setZero(n_);
  for (Eigen::VectorXd* v : {&x_pred_, &x_try_, &xdot_}) v->setZero(model.num_states());
  for (Eigen::VectorXd* v : {&r_pred_, &r_try_, &d_pred_, &d_try_, &d_plus_, &d_minus_}) {
    v->setZero(m_);
  }
}

std::string AlphaOs::Describe() const {
  return fmt::format("α-OS (Combescure & Pegon 1997), α = {}, β = {}, γ = {}, {}", alpha_, beta_,
                     gamma_, StepDescription());
}

void AlphaOs::Acceleration(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& r,
                           Eigen::VectorXd& out) {
  multibody::CalcStateDerivative<double>(model_, data_, t, x, r, xdot_);
  out = xdot_.tail(nv_);  // [u̇; ż]
}

void AlphaOs::OnStart() {
  Acceleration(point_.t, point_.x, point_.r, f_n_);
  a_ = f_n_;
  multibody::CalcSlotDisplacements<double>(model_, data_, point_.t, point_.x.head(n_), d_last_);
}

void AlphaOs::Predict(double h) {
  const auto q = point_.x.head(n_);
  const auto u = point_.x.segment(n_, n_);
  x_pred_.head(n_) = q + h * u + (h * h * (0.5 - beta_)) * a_.head(n_);
  x_pred_.tail(nv_) = point_.x.tail(nv_) + (h * (1.0 - gamma_)) * a_;
}

void AlphaOs::Step(SubstructureSeam& seam, RowSink& /*rows*/) {
  const long n = point_.step;
  // The step: fixed (t_{n+1} = (n+1) h, as exact as the RK schemes), or adaptive towards t_end.
  double h = StepToTake();
  if (config_.adaptive.enabled) {
    // Shorten (before anything moves) while the command would use too much of an increment.
    for (int k = 0; k < 20; ++k) {
      Predict(h);
      multibody::CalcSlotDisplacements<double>(model_, data_, point_.t + h, x_pred_.head(n_), d_pred_);
      if (IncrementRatio(d_pred_, d_last_, slots_.max_increment) <= kIncrementMargin ||
          h <= config_.adaptive.dt_min) {
        break;
      }
      h = std::max(config_.adaptive.dt_min, 0.5 * h);
    }
  }
  const double t_next = StepEnd(h);
  Predict(h);
  multibody::CalcSlotDisplacements<double>(model_, data_, t_next, x_pred_.head(n_), d_pred_);

  // The one specimen evaluation of the step.
  seam.Trial({n + 1, 0, t_next}, d_pred_, r_pred_);

  // Newton on a with the Jacobian at the predictor.
  // (allocation-free: the derivative workspace and the factorisations are built once)
  multibody::CalcStateJacobian(model_, derivatives_, t_next, x_pred_, r_pred_, J_);
  multibody::CalcCouplingMatrix(model_, derivatives_, t_next, x_pred_, B_);
  multibody::CalcStateDerivative<double>(model_, data_, t_next, x_pred_, r_pred_, xdot_);
  CalcSlotJacobian(model_, data_, t_next, x_pred_.head(n_), D_, q_scratch_, d_plus_, d_minus_);
  if (model_.has_constraints()) {
    // ∂u̇/∂r through the reduced equations (multibody/constraints.h).
    multibody::CalcConstrainedRateCoupling(model_, data_, B_, dfdr_);
  } else {
    mass_llt_.compute(data_.M);
    dfdr_ = B_;  // (n × m) ∂f_u/∂r = M⁻¹ B, a column at a time (no solver workspace)
    for (int s = 0; s < m_; ++s) mass_llt_.solveInPlace(dfdr_.col(s));
  }
  // Unknowns [a; w] (w = ż, the extra states' rates; none for most models): q moves with a,
  // [u; z] with [a; w]; the rates do not read r, so only the u̇ rows see M⁻¹ B K0 D.
  jac_.setIdentity();
  jac_.leftCols(n_).noalias() -= ((1.0 + alpha_) * beta_ * h * h) * J_.block(n_, 0, nv_, n_);
  if (coupled()) {
    dfdr_ = dfdr_ * slots_.k0_matrix;  // M⁻¹ B K0
  } else {
    dfdr_ = dfdr_ * slots_.k0.asDiagonal();
  }
  jac_.topLeftCorner(n_, n_).noalias() -= ((1.0 + alpha_) * beta_ * h * h) * dfdr_ * D_;
  jac_.noalias() -= ((1.0 + alpha_) * gamma_ * h) * J_.block(n_, n_, nv_, nv_);
  newton_lu_.compute(jac_);
  const auto& lu = newton_lu_;
  // The state and the split restoring forces r_pred + K0 (d − d_pred) for the acceleration
  // a_new_ (no allocation: members only).
  auto corrected_state = [&] {
    x_try_.head(n_) = x_pred_.head(n_) + (beta_ * h * h) * a_new_.head(n_);
    x_try_.tail(nv_) = x_pred_.tail(nv_) + (gamma_ * h) * a_new_;
    multibody::CalcSlotDisplacements<double>(model_, data_, t_next, x_try_.head(n_), d_try_);
    if (coupled()) {
      r_try_ = r_pred_;
      r_try_.noalias() += slots_.k0_matrix * d_try_;
      r_try_.noalias() -= slots_.k0_matrix * d_pred_;
    } else {
      r_try_ = r_pred_ + slots_.k0.cwiseProduct(d_try_ - d_pred_);
    }
  };
  a_new_ = a_;
  double scale = 1.0;
  bool converged = false;
  for (int it = 0; it < 50 && !converged; ++it) {
    corrected_state();
    Acceleration(t_next, x_try_, r_try_, f_try_);
    res_ = a_new_ - (1.0 + alpha_) * f_try_ + alpha_ * f_n_;
    if (it == 0) scale = std::max(1.0, f_try_.lpNorm<Eigen::Infinity>());
    delta_ = lu.solve(res_);
    a_new_ -= delta_;
    converged = delta_.lpNorm<Eigen::Infinity>() <= 1e-10 * scale;
  }
  if (!converged || !a_new_.allFinite()) {
    throw Error(fmt::format("α-OS: the corrector did not converge at t = {} s (step {}, h = {} s); "
                            "the specimen holds at the predictor. Reduce integrator.dt "
                            "(or adaptive.dt_max)", t_next, n + 1, h));
  }
  // Commit: the solution, its split restoring forces, F_{n+1} and the error estimate.
  corrected_state();
  double e = 0.0, h_next = h_;
  if (config_.adaptive.enabled) {
    a_step_ = (a_new_ - a_).head(n_);
    d_plus_.noalias() = D_ * a_step_;
    e = h * h * std::abs(beta_ - 1.0 / 6.0) * d_plus_.lpNorm<Eigen::Infinity>();
    h_next = NextStepSize(config_.adaptive, h, e, 3.0);
  }
  Acceleration(t_next, x_try_, r_try_, f_n_);
  a_ = a_new_;
  d_last_ = d_pred_;
  point_.step = n + 1;
  point_.t = t_next;
  point_.x = x_try_;
  point_.r = r_try_;
  // The next step within the stability guard's bound.
  if (config_.adaptive.enabled) ChooseNextStep(h, h_next, e, d_pred_, r_pred_);
}

nlohmann::json AlphaOs::SaveOwnState() const {
  nlohmann::json state = {{"a", ToJson(a_)}, {"f", ToJson(f_n_)}};
  SaveSplittingState(state);
  return state;
}

void AlphaOs::RestoreOwnState(const nlohmann::json& state) {
  RestoreSplittingState(state);
  a_ = VectorFromJson(state.at("a"), nv_, "alpha-os a");
  f_n_ = VectorFromJson(state.at("f"), nv_, "alpha-os f");
}

}  // namespace hybridtest::schemes
