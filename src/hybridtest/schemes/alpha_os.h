#pragma once
// AlphaOs: the α-operator-splitting scheme of Combescure & Pegon (1997, "α-Operator splitting
// time integration technique for pseudodynamic testing. Error propagation analysis", Soil
// Dynamics and Earthquake Engineering 16), after Nakashima et al. (1990), for the Kane model
// M(q) u̇ = g(t, q, u, r), q̇ = u. ONE specimen evaluation per step, none repeated.
//
// Parameters: α ∈ [−1/3, 0], β = (1 − α)²/4, γ = 1/2 − α. Step n → n+1 of size h:
//
//   predictor (explicit, imposed on the specimen once):
//     q̃ = q_n + h u_n + h² (1/2 − β) a_n          ũ = u_n + h (1 − γ) a_n
//     d̃ = d(t_{n+1}, q̃)                             r̃ = seam.Trial(d̃)
//   splitting: the restoring forces between the predictor and the solution are modelled with
//   the initial stiffness K0 (per slot):  r(q) = r̃ + K0 ∘ (d(t_{n+1}, q) − d̃)
//   corrector (implicit in the numerical model, no specimen motion):
//     q = q̃ + β h² a      u = ũ + γ h a
//     a_{n+1} solves  a = (1 + α) f_u(t_{n+1}, q, u, r(q)) − α F_n
//   with f_u = M⁻¹ g and F_n = f_u(t_n, q_n, u_n, r_n) at the committed point, by Newton's
//   method with the exact Jacobian
//     I − (1 + α) [ β h² (∂f_u/∂q + M⁻¹ B K0 D) + γ h ∂f_u/∂u ]
//   (∂f_u/∂x: the state Jacobian; B = ∂g/∂r the coupling matrix; D = ∂d/∂q), evaluated once
//   per step at the predictor. The committed r_{n+1} = r(q_{n+1}).
//
// For a linear system this is the scheme of the reference: unconditionally stable for a
// softening specimen (secant stiffness ≤ K0), second-order accurate, with numerical damping
// of high frequencies for α < 0. The stiff, purely numerical generator damping of the paper's
// rotor (eigenvalue −958 1/s) is handled implicitly, so h is set by accuracy alone.
//
// Adaptive step (optional, no rejections): the Zienkiewicz & Xie (1991, "A simple error
// estimator and adaptive time stepping procedure for dynamic analysis", Earthquake Eng. &
// Struct. Dyn. 20) local error estimate, measured on the slot displacements,
//     e = h² |β − 1/6| max_s | D (a_{n+1} − a_n) |_s
// sets the NEXT step (step_control.h, p = 3). Before the specimen moves, a step is shortened
// (never below dt_min) if the predicted command would use more than 80 % of a slot's
// max_increment. Stability with a stiffening specimen (tangent K_t > K0): the part ΔK = K_t − K0
// is explicit in the predictor, stable only while ω_Δ h < 2 (ω_Δ² = ΔK / m for one mass; in
// general the rise of λ² in the model's oscillatory modes); the adaptive step is capped at
// 0.8 · 2 / ω_Δ with ΔK estimated online from the samples, and halved and held after a growing
// error estimate (stability_guard.h).
//
// Extra first-order states z (model.h) ride with u: their rates w = ż take the place of a in
// the same formulas (z̃ = z_n + h (1 − γ) w_n, z = z̃ + γ h w, w = (1 + α) f_z − α W_n), so
// the corrector's unknowns are [a; w] and its Jacobian is the (n + nz) square of the same
// expression, exact (AutoDiff); for a linear rate this is the generalized trapezoidal rule.
//
// Requires q̇ = u (identity kinematical equations); refused otherwise with ConfigError.
#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "hybridtest/multibody/data.h"
#include "hybridtest/multibody/derivatives.h"
#include "hybridtest/multibody/model.h"
#include "hybridtest/schemes/operator_splitting.h"

namespace hybridtest::schemes {

class AlphaOs final : public OperatorSplittingScheme {
 public:
  // dt [s]: the step (fixed) or the first step (adaptive); `steps` = duration / dt when fixed.
  AlphaOs(const multibody::Model& model, const SchemeConfig& config, const SlotInfo& slots,
          double dt, double duration, long steps);

  std::string name() const override { return "alpha-os"; }
  std::string Describe() const override;
  void Step(SubstructureSeam& seam, RowSink& rows) override;

 protected:
  void OnStart() override;
  nlohmann::json SaveOwnState() const override;
  void RestoreOwnState(const nlohmann::json& state) override;

 private:
  // [f_u; f_z] at (t, [q; u; z], r) into out (n + nz).
  void Acceleration(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& r,
                    Eigen::VectorXd& out);
  // The predictor for a step of size h from the committed point into x_pred_.
  void Predict(double h);

  double alpha_, beta_, gamma_;
  int nv_;  // n + nz: the speeds and the extra states
  // Memory (part of the run state, with the base's): [a_n; w_n] and F_n (n + nz each).
  Eigen::VectorXd a_, f_n_;
  // Workspaces.
  Eigen::VectorXd x_pred_, x_try_, xdot_, r_pred_, r_try_, d_pred_, d_try_, f_try_, a_new_, res_, delta_,
      q_scratch_, d_plus_, d_minus_, a_step_;
  // (m×n), (nv×nv), (nx×nx), (n×m), (n×m)
  Eigen::MatrixXd D_, jac_, J_, B_, dfdr_;
  multibody::DerivativeWorkspace derivatives_;
  Eigen::LLT<Eigen::MatrixXd> mass_llt_;
  Eigen::PartialPivLU<Eigen::MatrixXd> newton_lu_;
};

}  // namespace hybridtest::schemes
