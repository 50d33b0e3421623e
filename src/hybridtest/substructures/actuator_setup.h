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
  void CalcSlotForces(const Eigen::Ref<const Eigen::VectorXd>& d,
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

 private:
  LinearSetup setup_;
};

}  // namespace hybridtest::substructures
