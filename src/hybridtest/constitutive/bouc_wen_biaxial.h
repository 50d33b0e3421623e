#pragma once
// BoucWenBiaxial: the coupled Bouc–Wen law of Park, Wen & Ang (1986) for a specimen loaded
// along n axes (biaxial for n = 2; any n ≥ 1), in the specimen's actuator coordinates.
//
//   F_i = α k_i u_i + (1 − α) k_i Y_i z_i                                  [N]
//   ż   = A v̇ − z ( β Σ_j |v̇_j z_j| + γ Σ_j v̇_j z_j ),   v_i = u_i / Y_i   (z: [-])
//
// u_i is the displacement along axis i [m], k_i its initial stiffness [N/m], Y_i its yield
// displacement [m], z the dimensionless hysteretic vector, α the post-yield stiffness ratio,
// A, β, γ the dimensionless shape parameters (the exponent is Park–Wen–Ang's 2). For n = 2 and
// Y_1 = Y_2 this is their Eq. (4):
//   Y ż_x = A u̇_x − β |u̇_x z_x| z_x − γ u̇_x z_x² − β |u̇_y z_y| z_x − γ u̇_y z_x z_y, and
//   the same with x and y exchanged.
// Properties (tested):
//   - motion along one axis (the other z_j = 0) is the one-dimensional BoucWen law
//     (bouc_wen.h) with n = 2, k0 = k_i, β' = β / Y_i², γ' = γ / Y_i²;
//   - with A = β + γ the unit ball |z| ≤ 1 is invariant: the hysteretic forces stay inside
//     the ellipse Σ_i (F_i − α k_i u_i)² / ((1 − α) k_i Y_i)² ≤ 1, the interaction (yield)
//     surface, and a large circular orbit runs along it;
//   - the virgin tangent is diag(k_i (α + (1 − α) A)).
//
// Integration: like BoucWen, z follows the straight path from the committed u to the trial u
// with classical RK4 in the path parameter, sub-stepped so that no sub-step moves any v_i by
// more than max_substep (default 1/200: the one-dimensional law's z_u / 200).
#include <vector>

#include "hybridtest/constitutive/vector_law.h"

namespace hybridtest::constitutive {

class BoucWenBiaxial final : public VectorRestoringForceLaw {
 public:
  struct Parameters {
    std::vector<double> initial_stiffness;   // k_i, one per axis. Unit: [N/m]. > 0.
    std::vector<double> yield_displacement;  // Y_i, one per axis. Unit: [m]. > 0.
    double alpha = 0.05;                     // α [-], in [0, 1].
    double a = 1.0;                          // A [-]. > 0.
    double beta = 0.5;                       // β [-]. β + γ > 0.
    double gamma = 0.5;                      // γ [-].
    double max_substep = 1.0 / 200.0;        // largest sub-step in v = u / Y [-]. > 0.
  };

  // Throws ConfigError naming the offending parameter.
  explicit BoucWenBiaxial(const Parameters& parameters);

  int num_axes() const override { return static_cast<int>(p_.initial_stiffness.size()); }
  void Trial(std::span<const double> u, std::span<double> force) override;
  void Commit() override;
  Eigen::MatrixXd initial_stiffness() const override;
  std::unique_ptr<VectorRestoringForceLaw> Clone() const override;
  std::string Describe() const override;
  // {"law": "bouc_wen_biaxial", "u": committed u [m], "z": committed z [-]}.
  nlohmann::json SaveState() const override;
  void RestoreState(const nlohmann::json& state) override;

  const Parameters& parameters() const { return p_; }
  const Eigen::VectorXd& committed_z() const { return z_committed_; }
  const Eigen::VectorXd& trial_z() const { return z_trial_; }

 private:
  // dz/ds along the path direction dv (n) [-].
  Eigen::VectorXd Slope(const Eigen::VectorXd& z, const Eigen::VectorXd& dv) const;

  Parameters p_;
  Eigen::VectorXd u_committed_, z_committed_, u_trial_, z_trial_;
};

}  // namespace hybridtest::constitutive
