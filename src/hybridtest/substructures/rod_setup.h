#pragma once
// RodSetup: the large-displacement geometry of n actuators on a specimen (OpenFresco's
// setups with nonlinear geometry, written from the geometry itself). Each actuator k is a
// rod pinned at a fixed base point b_k and at an attachment point on the specimen; each slot i
// is a translation of the attachment points along a direction e_i of the setup's frame
// (2-D or 3-D, SI). Rotational slots are not modelled: every attachment point moves with the
// same translation
//
//   D(d) = Σ_i d_i e_i                                   [m]     (E = [e_1 … e_m], dim × m)
//
// Actuator k, attached at c_k when d = 0 (L0_k = |c_k − b_k| > 0):
//
//   ℓ_k(d) = |c_k + D(d) − b_k|,   n_k(d) = (c_k + D(d) − b_k) / ℓ_k       (unit rod axis)
//   a_k    = p0_k + ℓ_k(d) − L0_k                                [m]  (the command)
//   J_ki   = ∂ℓ_k/∂d_i = n_k(d) · e_i                            [m/m]
//   r      = J(d)ᵀ f                                            [N]  (virtual work; f_k is
//                                                                     the force along rod k)
//   ∂²ℓ_k/∂d_i∂d_j = e_iᵀ (I − n_k n_kᵀ) e_j / ℓ_k                [1/m]
//
// At d = 0 it linearises to the linear setup with T = J(0) (rows: the rods' unit axes
// projected on the slot directions). A command grows with the rod's length: an actuator
// extends when its rod lengthens.
#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

#include "hybridtest/substructures/actuator_setup.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::substructures {

struct RodGeometry {
  Eigen::VectorXd p0;              // (n) actuator positions at zero specimen force [m]
  Eigen::MatrixXd directions;      // E (dim × m): slot i moves the specimen by d_i e_i [m/m]
  Eigen::MatrixXd bases;           // (dim × n) b_k, the fixed end of rod k [m]
  Eigen::MatrixXd attachments;     // (dim × n) c_k, rod k's end on the specimen at d = 0 [m]
  Eigen::VectorXd load_cell_zero;  // (n) readings at zero load, subtracted [N]

  int dimension() const { return static_cast<int>(directions.rows()); }
  int num_actuators() const { return static_cast<int>(bases.cols()); }
  int num_slots() const { return static_cast<int>(directions.cols()); }
};

class RodSetup final : public ActuatorSetup {
 public:
  // Shortest rod accepted [m].
  static constexpr double kMinRodLength = 1e-6;
  // Throws ConfigError (naming `slots`, `actuators[k].base`/`.attach`, `p0`, ...) if the sizes
  // do not fit (2 or 3 coordinates for every point and direction, one p0 and one load-cell
  // zero per rod), a value is not finite, a direction is zero, a rod is shorter than
  // kMinRodLength, or J(0) has not full column rank.
  explicit RodSetup(RodGeometry geometry);

  std::string kind() const override { return "large_displacement"; }
  int num_actuators() const override { return g_.num_actuators(); }
  int num_slots() const override { return g_.num_slots(); }
  const Eigen::VectorXd& p0() const override { return g_.p0; }
  const Eigen::VectorXd& load_cell_zero() const override { return g_.load_cell_zero; }
  const Eigen::MatrixXd& linearisation() const override { return t0_; }
  void CalcCommands(const Eigen::Ref<const Eigen::VectorXd>& d,
                    Eigen::Ref<Eigen::VectorXd> a) const override;
  Eigen::MatrixXd CalcJacobian(const Eigen::Ref<const Eigen::VectorXd>& d) const override;
  Eigen::MatrixXd CalcGeometricStiffness(const Eigen::Ref<const Eigen::VectorXd>& d,
                                         const Eigen::Ref<const Eigen::VectorXd>& f) const override;
  // max over sign vectors s ∈ {±1}^m of |E s| (a rod's length changes by at most the
  // attachment point's travel); Σ_i |e_i| for m > 12.
  double CommandStepBound(int k) const override;
  std::string Describe() const override;
  std::unique_ptr<ActuatorSetup> Clone() const override { return std::make_unique<RodSetup>(*this); }

  const RodGeometry& geometry() const { return g_; }
  // L0 (n) [m].
  const Eigen::VectorXd& rest_lengths() const { return l0_; }
  // ℓ(d) (n) [m]: the rods' lengths at d.
  Eigen::VectorXd CalcLengths(const Eigen::Ref<const Eigen::VectorXd>& d) const;

 private:
  // The rod vectors c_k + D(d) − b_k (dim × n) and their lengths; throws Error for a rod of
  // (nearly) zero length.
  void CalcRods(const Eigen::Ref<const Eigen::VectorXd>& d, Eigen::MatrixXd& rods,
                Eigen::VectorXd& lengths) const;

  RodGeometry g_;
  Eigen::VectorXd l0_;
  Eigen::MatrixXd t0_;
};

// Where J(d) gets close to singular within reach of the actuators. The scan visits a grid of
// the box |d_i| ≤ half_widths_i (m) [m] (at most about 4,000 points, at least 5 per slot, the
// corners and axes included) and keeps the points whose commands lie within every actuator's
// stroke (`limits`, one per actuator). It returns the first point where
//   σ_min(J(d)) < threshold · σ_min(J(0))     (or a rod shorter than RodSetup::kMinRodLength)
// i.e. where a slot force needs actuator forces 1/threshold times those at d = 0.
struct NearSingularPoint {
  Eigen::VectorXd d;     // (m) [m]
  double ratio = 0.0;    // σ_min(J(d)) / σ_min(J(0)) [-]
};
std::optional<NearSingularPoint> FindNearSingular(const RodSetup& setup,
                                                  const Eigen::VectorXd& half_widths,
                                                  const std::vector<transfer::SafetyLimits>& limits,
                                                  double threshold);

}  // namespace hybridtest::substructures
