#pragma once
// BoucWen: a smooth hysteretic restoring-force law (Bouc 1967, Wen 1976).
//
//   r(x, z) = α k0 x + (1 − α) k0 z
//   dz/dx   = A − |z|^n ( β sgn(ẋ z) + γ )                     (z has the unit of x: [m])
//
// x is the displacement [m], z the hysteretic displacement [m], k0 the initial stiffness [N/m],
// α the post-yield stiffness ratio, A, β, γ [1/m^n] and n the shape parameters.
// Properties (tested):
//   - tangent at the virgin state (x = z = 0): dr/dx = k0 (α + (1 − α) A), i.e. k0 when A = 1;
//   - z is bounded by the ultimate value z_u = (A / (β + γ))^{1/n} on loading branches, so for
//     a large monotonic excursion r → α k0 x + (1 − α) k0 z_u sgn(ẋ);
//   - a closed displacement cycle dissipates ∮ r dx > 0 when β > 0.
// The yield-displacement form (A = 1, β = γ = 1 / (2 x_y^n)) gives z_u = x_y, so x_y is the
// displacement at which the elastic branch k0·x would reach the plateau (1 − α) k0 x_y.
//
// Integration: z is integrated along the straight displacement path from the committed x to
// the trial x (the direction sgn(ẋ) is constant along it) with classical RK4 in x, sub-stepped
// so that no sub-step exceeds max_substep. A large trial increment therefore stays accurate.
#include <memory>
#include <string>

#include "hybridtest/constitutive/restoring_force_law.h"

namespace hybridtest::constitutive {

class BoucWen final : public RestoringForceLaw {
 public:
  struct Parameters {
    double initial_stiffness = 0.0;  // k0. Unit: [N/m]. > 0.
    double alpha = 0.05;             // post-yield stiffness ratio α, in [0, 1].
    double a = 1.0;                  // A [-]. > 0.
    double beta = 0.0;               // β. Unit: [1/m^n]. β + γ > 0.
    double gamma = 0.0;              // γ. Unit: [1/m^n].
    double n = 1.0;                  // sharpness exponent n ≥ 1.
    double max_substep = 0.0;        // largest RK4 sub-step in x. Unit: [m]. 0: z_u / 200.
  };

  // Throws ConfigError naming the offending parameter.
  explicit BoucWen(const Parameters& parameters);

  // The yield-displacement form: A = 1, β = γ = 1 / (2 x_y^n).
  // k0 [N/m], alpha [-], yield_displacement x_y [m] > 0, n ≥ 1.
  static Parameters FromYieldDisplacement(double initial_stiffness, double alpha,
                                          double yield_displacement, double n = 1.0);

  double Trial(double displacement) override;
  void Commit() override;
  double initial_stiffness() const override { return p_.initial_stiffness; }
  std::unique_ptr<RestoringForceLaw> Clone() const override;
  std::string Describe() const override;
  // {"x": committed x [m], "z": committed z [m]}; a restore also resets the trial to them.
  nlohmann::json SaveState() const override;
  void RestoreState(const nlohmann::json& state) override;

  const Parameters& parameters() const { return p_; }
  // Ultimate hysteretic displacement z_u = (A / (β + γ))^{1/n}. Unit: [m].
  double ultimate_z() const;
  // Committed displacement and hysteretic displacement. Unit: [m].
  double committed_displacement() const { return x_committed_; }
  double committed_z() const { return z_committed_; }

 private:
  double CalcSlope(double z, double direction) const;  // dz/dx along `direction` = ±1
  double CalcForce(double x, double z) const;

  Parameters p_;
  double x_committed_ = 0.0;
  double z_committed_ = 0.0;
  double x_trial_ = 0.0;
  double z_trial_ = 0.0;
};

}  // namespace hybridtest::constitutive
