#pragma once
// ActuatorSetup: the geometry of a test setup with n actuators on a specimen that serves m
// slots, as the substructure, its safety and its numerical twin see it. Two kinds:
//
//   linear               (LinearSetup, linear_setup.h)   a = p0 + T d,             r = Tᵀ f
//   large_displacement   (RodSetup, rod_setup.h)         a = p0 + ℓ(d) − L0,       r = J(d)ᵀ f
//
// with d (m) the slot displacements [m], a (n) the actuator commands [m], f (n) the measured
// actuator forces after the load-cell zero [N] and r (m) the slot restoring forces [N]. In
// both, J(d) = ∂a/∂d (n × m) and r = J(d)ᵀ f is virtual work: f_k δa_k summed over the
// actuators equals r · δd. The linearisation T0 = J(0) is what K0, the coupled force
// prediction of the gate and the plan's linear twin use; for the linear kind J(d) = T0 = T.
//
// The tangent of r for a specimen of stiffness K_a in actuator coordinates (f = K_a (a − p0)):
//
//   dr/dd = J(d)ᵀ K_a J(d) + Σ_k f_k ∂²a_k/∂d²            (m × m) [N/m]
//
// The second term (CalcGeometricStiffness) is zero for the linear kind, and zero at zero
// actuator force for every kind: at d = 0 with p0 at zero specimen force, K0 = T0ᵀ K_a T0.
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <memory>
#include <string>

#include "hybridtest/substructures/linear_setup.h"
#include "hybridtest/substructures/setup_transform.h"

namespace hybridtest::substructures {

class ActuatorSetup {
 public:
  virtual ~ActuatorSetup() = default;

  // "linear" or "large_displacement" (the config's `setup.geometry`).
  virtual std::string kind() const = 0;
  virtual int num_actuators() const = 0;
  virtual int num_slots() const = 0;
  // (n) actuator positions at zero specimen force [m].
  virtual const Eigen::VectorXd& p0() const = 0;
  // (n) load-cell readings at zero load, subtracted from the measured forces [N].
  virtual const Eigen::VectorXd& load_cell_zero() const = 0;
  // T0 = J(0) (n × m) [m/m].
  virtual const Eigen::MatrixXd& linearisation() const = 0;

  // a (n) [m] from d (m) [m]. Throws Error where the geometry is degenerate (a rod of zero
  // length).
  virtual void CalcCommands(const Eigen::Ref<const Eigen::VectorXd>& d,
                            Eigen::Ref<Eigen::VectorXd> a) const = 0;
  // J(d) = ∂a/∂d (n × m) [m/m].
  virtual Eigen::MatrixXd CalcJacobian(const Eigen::Ref<const Eigen::VectorXd>& d) const = 0;
  // r = J(d)ᵀ f (m) [N] for the forces f (n) [N] measured at d.
  virtual void CalcSlotForces(const Eigen::Ref<const Eigen::VectorXd>& d,
                      const Eigen::Ref<const Eigen::VectorXd>& f,
                      Eigen::Ref<Eigen::VectorXd> r) const;
  // Σ_k f_k ∂²a_k/∂d² (m × m) [N/m] at d with forces f (n) [N]; zero for the linear kind.
  virtual Eigen::MatrixXd CalcGeometricStiffness(const Eigen::Ref<const Eigen::VectorXd>& d,
                                                 const Eigen::Ref<const Eigen::VectorXd>& f) const = 0;
  // A bound, valid at every d, of |a_k(d + Δ) − a_k(d)| / max_i |Δ_i| [m/m]: how far actuator
  // k can move when no slot moves by more than one unit.
  virtual double CommandStepBound(int k) const = 0;
  // One line for logs and the sidecar's description.
  virtual std::string Describe() const = 0;
  virtual std::unique_ptr<ActuatorSetup> Clone() const = 0;

  // K0 = dr/dd at d = 0 (m × m) [N/m] of a specimen of stiffness K_a (n × n) [N/m] in actuator
  // coordinates: T0ᵀ K_a T0.
  virtual Eigen::MatrixXd SlotStiffness(const Eigen::MatrixXd& actuator_k) const;
  // The inverse map, K_a = T0⁺ᵀ K0 T0⁺ (n × n) [N/m] with T0⁺ = (T0ᵀT0)⁻¹T0ᵀ (T0⁻ᵀ K0 T0⁻¹
  // for a square T0): what the safety gate predicts forces with when K0 is given.
  virtual Eigen::MatrixXd ActuatorStiffness(const Eigen::MatrixXd& k0) const;
  // a = p0 + d and r = f with no load-cell zero (one actuator, one slot): the emulated
  // specimen's law then is the slot's law as is (twin.h).
  virtual bool is_identity() const { return false; }
};

// The linear setup behind the interface: a = p0 + T d, r = Rᵀ f (R = T unless the load cells
// read through another factor, linear_setup.h), J = T. One actuator and one slot
// (`setup: {p0, sign, scale, ...}`) is its case n = m = 1 (OneActuatorSetup), computed in
// scalars: a = p0 + (sign · scale) · d and r = (force_sign · force_scale) · f, bit for bit
// the arithmetic a one-actuator run always had.
class LinearActuatorSetup final : public ActuatorSetup {
 public:
  // Throws ConfigError as LinearSetup::Validate does.
  explicit LinearActuatorSetup(LinearSetup setup);

  std::string kind() const override { return "linear"; }
  int num_actuators() const override { return setup_.num_actuators(); }
  int num_slots() const override { return setup_.num_slots(); }
  const Eigen::VectorXd& p0() const override { return setup_.p0; }
  const Eigen::VectorXd& load_cell_zero() const override { return setup_.load_cell_zero; }
  const Eigen::MatrixXd& linearisation() const override { return setup_.transform; }
  void CalcCommands(const Eigen::Ref<const Eigen::VectorXd>& d,
                    Eigen::Ref<Eigen::VectorXd> a) const override {
    if (scalar_) {
      a(0) = setup_.p0(0) + setup_.transform(0, 0) * d(0);
    } else {
      a.noalias() = setup_.p0 + setup_.transform * d;
    }
  }
  Eigen::MatrixXd CalcJacobian(const Eigen::Ref<const Eigen::VectorXd>& /*d*/) const override {
    return setup_.transform;
  }
  // r = Rᵀ f.
  void CalcSlotForces(const Eigen::Ref<const Eigen::VectorXd>& d,
                      const Eigen::Ref<const Eigen::VectorXd>& f,
                      Eigen::Ref<Eigen::VectorXd> r) const override;
  Eigen::MatrixXd CalcGeometricStiffness(const Eigen::Ref<const Eigen::VectorXd>& /*d*/,
                                         const Eigen::Ref<const Eigen::VectorXd>& /*f*/) const override {
    return Eigen::MatrixXd::Zero(num_slots(), num_slots());
  }
  // Σ_i |T_ki|.
  double CommandStepBound(int k) const override { return setup_.transform.row(k).cwiseAbs().sum(); }
  std::string Describe() const override;
  std::unique_ptr<ActuatorSetup> Clone() const override {
    return std::make_unique<LinearActuatorSetup>(*this);
  }
  // Rᵀ K_a T (m × m) [N/m], and its inverse R⁺ᵀ K0 T⁺ (n × n) [N/m] (for n = m = 1:
  // K_a · T · R and K0 / (T · R)).
  Eigen::MatrixXd SlotStiffness(const Eigen::MatrixXd& actuator_k) const override;
  Eigen::MatrixXd ActuatorStiffness(const Eigen::MatrixXd& k0) const override;
  const LinearSetup& data() const { return setup_; }
  // n = m = 1, T = R = [1], no load-cell zero.
  bool is_identity() const override {
    return scalar_ && setup_.transform(0, 0) == 1.0 && force_map()(0, 0) == 1.0 &&
           setup_.load_cell_zero(0) == 0.0;
  }

 private:
  // R: the force transform, or T.
  const Eigen::MatrixXd& force_map() const {
    return setup_.force_transform.size() > 0 ? setup_.force_transform : setup_.transform;
  }

  LinearSetup setup_;
  bool scalar_ = false;  // n = m = 1
};

// The one-actuator setup of `setup: {p0, sign, scale, force_sign, force_scale,
// load_cell_zero}` (setup_transform.h) as the linear setup of n = m = 1: p0 = [p0],
// T = [sign · scale], R = [force_sign · force_scale], load_cell_zero = [load_cell_zero].
// Throws ConfigError as SetupTransform::Validate does.
LinearSetup OneActuatorSetup(const SetupTransform& transform);

}  // namespace hybridtest::substructures
