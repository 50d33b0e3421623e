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

// The one-actuator setup (setup_transform.h) behind the interface: n = m = 1,
//   a = p0 + sign · scale · d          [m]
//   r = force_sign · force_scale · f   [N]   (f after the load-cell zero)
// in SetupTransform's own arithmetic (bit for bit the same as a one-actuator run always was).
class ScalarSetup final : public ActuatorSetup {
 public:
  // Throws ConfigError as SetupTransform::Validate does.
  explicit ScalarSetup(const SetupTransform& transform);

  std::string kind() const override { return "linear"; }
  int num_actuators() const override { return 1; }
  int num_slots() const override { return 1; }
  const Eigen::VectorXd& p0() const override { return p0_; }
  const Eigen::VectorXd& load_cell_zero() const override { return zero_; }
  const Eigen::MatrixXd& linearisation() const override { return t_; }
  void CalcCommands(const Eigen::Ref<const Eigen::VectorXd>& d,
                    Eigen::Ref<Eigen::VectorXd> a) const override {
    a(0) = s_.CommandMetres(d(0));
  }
  Eigen::MatrixXd CalcJacobian(const Eigen::Ref<const Eigen::VectorXd>& /*d*/) const override {
    return t_;
  }
  void CalcSlotForces(const Eigen::Ref<const Eigen::VectorXd>& /*d*/,
                      const Eigen::Ref<const Eigen::VectorXd>& f,
                      Eigen::Ref<Eigen::VectorXd> r) const override {
    r(0) = s_.RestoringForce(f(0));
  }
  Eigen::MatrixXd CalcGeometricStiffness(const Eigen::Ref<const Eigen::VectorXd>& /*d*/,
                                         const Eigen::Ref<const Eigen::VectorXd>& /*f*/) const override {
    return Eigen::MatrixXd::Zero(1, 1);
  }
  // |sign · scale| = scale.
  double CommandStepBound(int /*k*/) const override { return s_.scale; }
  std::string Describe() const override;
  std::unique_ptr<ActuatorSetup> Clone() const override {
    return std::make_unique<ScalarSetup>(*this);
  }
  // K_a · sign · scale · force_sign · force_scale, and its inverse.
  Eigen::MatrixXd SlotStiffness(const Eigen::MatrixXd& actuator_k) const override;
  Eigen::MatrixXd ActuatorStiffness(const Eigen::MatrixXd& k0) const override;
  bool is_identity() const override {
    return s_.sign == 1.0 && s_.scale == 1.0 && s_.force_sign == 1.0 && s_.force_scale == 1.0 &&
           s_.load_cell_zero == 0.0;
  }
  const SetupTransform& transform() const { return s_; }

 private:
  SetupTransform s_;
  Eigen::VectorXd p0_, zero_;  // (1)
  Eigen::MatrixXd t_;          // [sign · scale] (1 × 1)
};

// The linear setup behind the interface: a = p0 + T d, r = Tᵀ f, J = T.
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
    a.noalias() = setup_.p0 + setup_.transform * d;
  }
  Eigen::MatrixXd CalcJacobian(const Eigen::Ref<const Eigen::VectorXd>& /*d*/) const override {
    return setup_.transform;
  }
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
  const LinearSetup& data() const { return setup_; }
  // n = m = 1, T = [1], no load-cell zero.
  bool is_identity() const override {
    return num_actuators() == 1 && num_slots() == 1 && setup_.transform(0, 0) == 1.0 &&
           setup_.load_cell_zero(0) == 0.0;
  }

 private:
  LinearSetup setup_;
};

}  // namespace hybridtest::substructures
