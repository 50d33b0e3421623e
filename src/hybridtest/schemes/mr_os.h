#pragma once
// MrOs: multi-rate operator splitting. The numerical model is subcycled with fine explicit
// RK4 substeps; the specimen is sampled ONCE per macro step; between samples the restoring
// forces are modelled as r(t, q) = K0 ∘ d(t, q) + ρ(t), where ρ = r − K0 d is the residual
// the initial stiffness does not explain, reconstructed from the samples. A combination of
// established parts: operator splitting with K0 (Nakashima et al. 1990), subcycling of the
// numerical part (Dermitzakis & Mahin 1985), a predictor–corrector on the residual, and
// Milne-type step control (the difference between predictor and corrector).
//
// Samples (T_j, d_j, r_j), residuals ρ_j = r_j − K0 ∘ d_j. Macro step [T_k, T_{k+1}], H:
//   predict   integrate x from x_k with RK4 substeps ≤ `substep`, using ρ_P(t) = the linear
//             extrapolation through (T_{k−1}, ρ_{k−1}), (T_k, ρ_k) (constant at the start);
//             d_{k+1} = d(T_{k+1}, q_P(T_{k+1}))
//   evaluate  seam.Trial at the predicted state: the specimen moves to d_{k+1} once, r_{k+1}
//   correct   integrate again from x_k with ρ_C(t) = the quadratic through T_{k−1}, T_k,
//             T_{k+1} (linear at the start); no specimen motion. x_{k+1} = x_C(T_{k+1}),
//             committed r_{k+1} = K0 ∘ d(T_{k+1}, q_C) + ρ_{k+1}. The corrector's substeps
//             are journalled as intermediate rows (their r is the modelled one).
//   control   (adaptive) e = max_s |d_s(T_{k+1}, q_C) − d_{k+1,s}|, the distance between the
//             imposed and the corrected displacement (O(H³)); the next H from step_control.h
//             with p = 3, within [dt_min, dt_max]. Before the specimen moves, H is halved
//             (down to dt_min) while the predicted command would use more than 80 % of a
//             slot's max_increment.
//   stability (adaptive) the residual ρ is extrapolated, so the stiffness K0 does not explain
//             (ΔK = K_t − K0 > 0: K0 too soft, or a hardening specimen) is integrated
//             explicitly: stable only while ω_Δ H < 1.34, ω_Δ² the rise of λ² that ΔK causes
//             in the model's oscillatory modes (ΔK / m for one mass). The next H is capped at
//             0.8 · 1.34 / ω_Δ with ΔK from the tangent stiffness estimated online from the
//             samples, and halved and held after a growing error estimate (stability_guard.h).
//
// Numerical slots go through the same split (their law's K0 makes ρ ≡ 0 for a linear
// spring, so they are then exact at every substep). Any kinematical equations q̇ = W(q) u.
// Substeps must respect RK4's stability limit for the model (the rotor: ≤ 2.9 ms).
#include "hybridtest/integrators/explicit_runge_kutta.h"
#include "hybridtest/multibody/data.h"
#include "hybridtest/multibody/model.h"
#include "hybridtest/schemes/operator_splitting.h"

namespace hybridtest::schemes {

class MrOs final : public OperatorSplittingScheme {
 public:
  // dt [s]: the macro step (fixed) or the first macro step (adaptive).
  MrOs(const multibody::Model& model, const SchemeConfig& config, const SlotInfo& slots,
       double dt, double duration, long steps);

  std::string name() const override { return "mr-os"; }
  std::string Describe() const override;
  void Step(SubstructureSeam& seam, RowSink& rows) override;

 protected:
  void OnStart() override;
  nlohmann::json SaveOwnState() const override;
  void RestoreOwnState(const nlohmann::json& state) override;

 private:
  // Residual model ρ(t) (m) from the samples: `with_new` uses (T_{k+1}, ρ_{k+1}) too.
  void Residual(double t, bool with_new, Eigen::VectorXd& rho) const;
  // Integrates from the committed point over h to x_end with the residual model; emits the
  // substep rows (all but the last) if `rows` is given.
  void Integrate(double h, bool with_new, Eigen::VectorXd& x_end, RowSink* rows);

  integrators::ExplicitRungeKutta rk4_;
  // Memory (part of the run state, with the base's): the last two samples' times and
  // residuals (the older one is absent at the start).
  int samples_ = 0;   // 1 or 2 once started
  double t_prev_ = 0.0, t_cur_ = 0.0, t_new_ = 0.0;
  Eigen::VectorXd rho_prev_, rho_cur_, rho_new_;
  // Workspaces.
  Eigen::VectorXd x_pred_, x_corr_, x_sub_, d_, rho_, r_, r_sample_;
};

}  // namespace hybridtest::schemes
