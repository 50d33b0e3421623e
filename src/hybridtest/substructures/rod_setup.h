#pragma once
// RodSetup: the large-displacement geometry of n actuators on a specimen (OpenFresco's
// setups with nonlinear geometry, written from the geometry itself). Each actuator k is a
// rod pinned at a fixed base point b_k and at an attachment point on the specimen; each slot i
// is a translation of the specimen (a rigid body) along a direction e_i of the setup's frame
// (2-D or 3-D, SI), and at most one slot θ may instead turn it [rad] about an axis a through a
// point o (2-D: about o, in the plane). Rotations about several axes are not modelled. The
// attachment point of actuator k, at c_k when d = 0, moves to
//
//   p_k(d) = c_k + Σ_{i translational} d_i e_i + (R(θ) − I)(c_k − o)       [m]
//
// and with L0_k = |c_k − b_k| > 0:
//
//   ℓ_k(d) = |p_k(d) − b_k|,   n_k(d) = (p_k(d) − b_k) / ℓ_k                (unit rod axis)
//   a_k    = p0_k + ℓ_k(d) − L0_k                                [m]  (the command)
//   J_ki   = ∂ℓ_k/∂d_i = n_k · g_ki,   g_ki = ∂p_k/∂d_i          [m/m] or [m/rad]
//            (g = e_i for a translation, a × R(θ)(c_k − o) for the rotation)
//   r      = J(d)ᵀ f                                            [N] or [N·m] (virtual work;
//                                                                     f_k along rod k)
//   ∂²ℓ_k/∂d_i∂d_j = g_kiᵀ (I − n_k n_kᵀ) g_kj / ℓ_k + n_k · ∂²p_k/∂d_i∂d_j
//            (the last term only for i = j = θ: a × (a × R(θ)(c_k − o)))
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
  // The rotational slot (−1: none); its column of `directions` is not used (zero). It turns the
  // specimen by d_i [rad] about the axis through rotation_point (dim) [m] along rotation_axis
  // (3-D: any non-zero vector, normalised; 2-D: unused, the plane's normal).
  int rotation_slot = -1;
  Eigen::VectorXd rotation_point;
  Eigen::VectorXd rotation_axis;

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
  // attachment point's travel; Σ_i |e_i| for m > 12), plus the attachment point's distance from
  // the rotation axis (a chord is shorter than its arc) if a slot rotates.
  double CommandStepBound(int k) const override;
  std::string Describe() const override;
  std::unique_ptr<ActuatorSetup> Clone() const override { return std::make_unique<RodSetup>(*this); }

  const RodGeometry& geometry() const { return g_; }
  // L0 (n) [m].
  const Eigen::VectorXd& rest_lengths() const { return l0_; }
  // ℓ(d) (n) [m]: the rods' lengths at d.
  Eigen::VectorXd CalcLengths(const Eigen::Ref<const Eigen::VectorXd>& d) const;
  // Actuator k's attachment point's distance from the rotation axis [m] (0 without one).
  double lever_arm(int k) const;

 private:
  // The rod vectors p_k(d) − b_k (dim × n), their lengths and the turned arms R(θ)(c_k − o)
  // (dim × n; zero without a rotation); throws Error for a rod of (nearly) zero length.
  void CalcRods(const Eigen::Ref<const Eigen::VectorXd>& d, Eigen::MatrixXd& rods,
                Eigen::VectorXd& lengths, Eigen::MatrixXd& arms) const;
  // a × v (2-D: v turned by +90°).
  Eigen::VectorXd Cross(const Eigen::VectorXd& v) const;
  // g_k (dim × m): ∂p_k/∂d at the turned arm w = R(θ)(c_k − o).
  Eigen::MatrixXd SlotGradients(const Eigen::VectorXd& arm) const;

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
