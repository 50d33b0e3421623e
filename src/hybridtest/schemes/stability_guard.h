#pragma once
// StabilityGuard: keeps the adaptive step of an operator-splitting scheme (alpha_os.h,
// mr_os.h) inside the stability bound that the error of the initial stiffness K0 sets, and
// shortens the next steps when the scheme's own error estimate shows a growing oscillation.
// It uses only the samples the scheme takes anyway (no extra specimen evaluation).
//
// Why a bound. The splitting models the restoring force as K0 ∘ d plus a part it learns from
// the samples. The part K0 does not explain, (K_t − K0) ∘ d with K_t the specimen's tangent
// stiffness, is therefore treated explicitly. Where K_t > K0 (K0 too soft, or a hardening
// specimen), that explicit part is a stiffness ΔK = K_t − K0 > 0 on the slot. For a mode of
// the linearised model with K0 (eigenvalue λ, oscillatory: |Im λ| > |Re λ|) it raises λ² by
//
//   ω_Δ² = −Re(2 λ dλ),   dλ = first-order change of λ under ΔK (left/right eigenvectors)
//
// (for an undamped oscillator of mass m: ω_Δ² = ΔK / m = ω_t² − ω_0², exactly). The
// linearisation is A = ∂ẋ/∂x + ∂ẋ/∂r diag(K0) ∂d/∂x at the committed point (by differences;
// the model is linear in r), so a degree of freedom held by a stiff damper (the rotor's hub,
// eigenvalue −958 1/s) does not count as mass the slot drives. An explicit treatment of a
// stiffness is stable only while ω_Δ h stays below a constant c of the scheme, measured on the
// undamped single-degree-of-freedom oscillator (beyond it the free vibration grows by more
// than 1 % of ω0 per unit time):
//
//   MR-OS (linear extrapolation / quadratic correction of the residual)   c = 1.34
//           (1.31–1.35 for K0 from K_t/4 to K_t/1.3; 1.20 at K_t/1.2)
//   α-OS (α = −0.05, explicit predictor)                                  c = 2.0
//           (2.02–2.04 for K0 from K_t/4 to K_t/1.2; 1.90 at K_t/1.1)
//
// The margin below covers the spread.
// A step beyond it is not merely inaccurate: the blade mode grows by orders of magnitude
// within a few steps, and the specimen cannot be un-moved. The guard caps the next step at
//
//   h ≤ kStabilityMargin · c / max over the oscillatory modes of ω_Δ,   kStabilityMargin = 0.8,
//
// with ΔK⁺_s = max(0, K̂_s − K0_s − 2 σ_s): the estimated tangent stiffness K̂ less two
// standard errors of the estimate, so that load-cell noise alone does not shorten the steps
// of a test whose K0 is right. Where K_t ≤ K0 (softening, or K0 too stiff) the splitting is
// unconditionally stable and the guard sets no bound.
//
// Tangent stiffness online. Between consecutive samples (d_j, r_j) of slot s, the increments
// Δd, Δr are fitted by least squares through the origin with exponential forgetting
// (kForgetting = 0.7 per sample, about the last 3 samples):
//   K̂ = S_dr / S_dd,   σ² = (S_rr − K̂ S_dr) / ((n − 1) S_dd),   n = Σ weights,
// so that small moves (where noise dominates) weigh little. No estimate (ΔK⁺ = 0) before
// three increments.
//
// Growing oscillation. A mode that grows faster than the step control can follow shows as a
// local error estimate e (the difference between the imposed and the corrected displacement,
// largest over the slots) that keeps growing although the controller shortens the steps.
// When |e| has grown by more than kGrowth twice in a row, from above twice the tolerance,
// over steps that did not lengthen, the guard halves the next step and keeps the step from
// growing for kHoldSteps steps (the controller alone would double it back into the
// oscillation). Load-cell noise makes single large estimates common; three in a row, growing,
// it does not make (none in the 16 runs of emulated-fast.yaml with K0 × 0.5 and × 1, seeds
// 1–8, with the guard off).
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <nlohmann/json.hpp>

#include <limits>

#include "hybridtest/multibody/data.h"
#include "hybridtest/multibody/model.h"

namespace hybridtest::schemes {

inline constexpr double kStabilityMargin = 0.8;
inline constexpr double kMrOsStabilityConstant = 1.34;
inline constexpr double kAlphaOsStabilityConstant = 2.0;

class StabilityGuard {
 public:
  static constexpr double kForgetting = 0.7;
  static constexpr double kGrowth = 1.2;
  static constexpr int kHoldSteps = 4;

  // n coordinates, m slots; `constant` is the scheme's c above.
  StabilityGuard(int num_coordinates, int num_slots, double constant);

  // A new sample of every slot: imposed displacement d (m) [m], measured force r (m) [N].
  void AddSample(const Eigen::VectorXd& d, const Eigen::VectorXd& r);
  // The scheme's local error estimate e [m] of the step of size h [s] just taken, and the
  // tolerance [m].
  void AddErrorEstimate(double e, double h, double tolerance);

  // The modes of the linearised model with K0 (m) at (t, x (2n), r (m)). Allocation-free.
  void UpdateModes(const multibody::Model& model, multibody::Data<double>& data, double t,
                      const Eigen::VectorXd& x, const Eigen::VectorXd& r,
                      const Eigen::VectorXd& k0);

  // The next step, capped by the bound for K0 (m) and by a detected oscillation: `h_next` [s]
  // as the step controller chose it after a step of size `h` [s]; never below dt_min [s].
  double Limit(double h_next, double h, double dt_min, const Eigen::VectorXd& k0);

  // True if some slot's tangent stiffness exceeds its K0 (m) by more than two standard
  // errors: only then is there a bound, and only then do the modes need updating.
  bool HasExcess(const Eigen::VectorXd& k0) const;
  // The current bound on the step [s] (+inf when none) for K0 (m).
  double StableStep(const Eigen::VectorXd& k0) const;
  // K̂_s [N/m] (NaN before three increments) and its standard error σ_s.
  double tangent_stiffness(int s) const;
  double tangent_stiffness_error(int s) const;
  // Steps the guard has shortened so far (by the bound or an oscillation).
  long shortened_steps() const { return shortened_; }

  nlohmann::json SaveState() const;
  // Restores what SaveState() wrote; a state without a guard (older run states) starts afresh.
  void RestoreState(const nlohmann::json& state);

 private:
  int n_, m_;
  double constant_;
  int samples_ = 0;
  Eigen::VectorXd d_last_, r_last_, s_dd_, s_dr_, s_rr_, n_eff_;  // (m) each
  double e_[3] = {0.0, 0.0, 0.0};  // |e| [m] of the last three steps, newest first
  double h_[3] = {0.0, 0.0, 0.0};  // their sizes [s]
  int errors_ = 0;
  int hold_ = 0;
  bool oscillating_ = false;
  long shortened_ = 0;
  // The modes at the last committed point: eigenvalues λ (2n), Q = V⁻¹ ∂ẋ/∂r (2n × m) and
  // R = ∂d/∂x V (m × 2n), V the real pseudo-eigenvectors; modes_ = false before the first.
  bool modes_ = false;
  Eigen::VectorXcd lambda_;
  Eigen::MatrixXd Q_, R_;
  // Workspaces.
  Eigen::VectorXd x_scratch_, xdot_plus_, xdot_minus_, r_scratch_, d_plus_, d_minus_;
  Eigen::MatrixXd A_, Jr_, Dx_;
  Eigen::EigenSolver<Eigen::MatrixXd> eigen_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
};

}  // namespace hybridtest::schemes
