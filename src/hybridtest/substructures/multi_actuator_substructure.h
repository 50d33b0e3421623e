#pragma once
// MultiActuatorSubstructure: a specimen moved by n actuators that serves m slots of the model
// (a blade tip in flap and edge), reached through one TransferSystem of n actuators, a setup
// (actuator_setup.h: linear, a = p0 + T d and r = Tᵀ f, or large-displacement, a = p0 + ℓ(d)
// − L0 and r = J(d)ᵀ f) and a SafetyGateGroup (one monitor per actuator, every command
// checked before any actuator moves), with optional limits per slot (slot_limits.h). On any
// violation or communication failure the transfer system holds (every actuator) and the error
// propagates.
#include <memory>
#include <optional>
#include <vector>

#include "hybridtest/substructures/actuator_setup.h"
#include "hybridtest/substructures/linear_setup.h"
#include "hybridtest/substructures/slot_limits.h"
#include "hybridtest/substructures/substructure.h"
#include "hybridtest/transfer/safety_gate_group.h"

namespace hybridtest::substructures {

class MultiActuatorSubstructure final : public Substructure {
 public:
  // limits: one per actuator. Throws ConfigError if the setup, the limits and the transfer
  // system's actuators do not fit together.
  MultiActuatorSubstructure(std::string name, std::unique_ptr<transfer::TransferSystem> transfer,
                            LinearSetup setup, std::vector<transfer::SafetyLimits> limits);
  MultiActuatorSubstructure(std::string name, std::unique_ptr<transfer::TransferSystem> transfer,
                            std::unique_ptr<ActuatorSetup> setup,
                            std::vector<transfer::SafetyLimits> limits);
  ~MultiActuatorSubstructure() override;

  void Activate() override;
  // One slot only (Error otherwise): the seam calls TrialSlots.
  double Trial(double displacement, const TrialContext& context) override;
  int num_slots() const override { return setup_->num_slots(); }
  void TrialSlots(std::span<const double> d, std::span<double> r,
                  const TrialContext& context) override;
  void Commit() override {}
  void Hold() noexcept override;
  void Deactivate() override;
  bool is_physical() const override { return true; }
  int num_actuators() const override { return setup_->num_actuators(); }
  Exchange last_exchange() const override { return last_[0]; }
  Exchange actuator_exchange(int k) const override { return last_[static_cast<std::size_t>(k)]; }
  long evaluations() const override { return evaluations_; }
  std::string Describe() const override;
  std::optional<double> initial_stiffness() const override;
  std::optional<Eigen::MatrixXd> initial_stiffness_matrix() const override { return k0_; }
  // The largest change of every slot displacement that keeps every actuator's command step
  // within its max_increment, at any d: min_k max_increment_k / B_k [m], with B_k the setup's
  // CommandStepBound (Σ_i |T_ki| for a linear setup).
  double max_displacement_increment() const override;
  nlohmann::json SaveState() const override;
  void RestoreState(const nlohmann::json& state) override;

  const ActuatorSetup& setup() const { return *setup_; }
  // Limits per slot (max_displacement [m], max_force [N]), checked on every trial. Throws
  // ConfigError unless each list has one positive value per slot (+inf: none).
  void SetSlotLimits(SlotLimits limits);
  const std::optional<SlotLimits>& slot_limits() const { return slot_limits_; }
  const transfer::SafetyGateGroup& safety() const { return gate_; }
  transfer::TransferSystem& transfer() { return *transfer_; }
  const transfer::TransferSystem& transfer() const { return *transfer_; }

  // K0 = dr/dd (m × m) [N/m].
  void SetInitialStiffness(const Eigen::MatrixXd& k0);
  // Measures K0 before the test: each actuator in turn ramps from p0 to p0 + amplitude and back
  // in equal moves (each at most half its max_increment; the others stay at p0); the
  // symmetric actuator stiffness K_a (n × n) is fitted by least squares to all samples, and
  // K0 = T0ᵀ K_a T0 with T0 = J(0) (exact at d = 0: the setup's geometric stiffness
  // Σ f_k ∂²a_k/∂d² vanishes at zero force). Each move is a specimen evaluation.
  // amplitude [m] > 0.
  struct StiffnessMeasurement {
    Eigen::MatrixXd k0;            // m × m [N/m]
    Eigen::MatrixXd actuator_k;    // n × n [N/m]
    double amplitude = 0.0;        // [m]
    std::vector<std::pair<Eigen::VectorXd, Eigen::VectorXd>> samples;  // (a − p0 [m], f [N])
  };
  StiffnessMeasurement MeasureInitialStiffness(double amplitude);
  void RequestStiffnessMeasurement(double amplitude) { k0_ramp_ = amplitude; }
  std::optional<double> requested_stiffness_ramp() const { return k0_ramp_; }

  // Resume: re-imposes every actuator's last committed command at once (all actuators move
  // together, every command checked) and compares each force with the committed one within
  // force_tolerance [N] (≤ 0: 1 % of that actuator's force_hard). Throws SafetyStop (limit
  // "resume_force_tolerance") after putting the bench on hold.
  void ReimposeCommitted(double force_tolerance, long step);

 private:
  void MoveAll(const std::vector<double>& commands, transfer::MoveLabel label);
  // Throws SafetyStop (after holding) if a slot displacement (before) or force (after) is
  // beyond its slot limit.
  void CheckSlotDisplacements(std::span<const double> d, const TrialContext& ctx);
  void CheckSlotForces(std::span<const double> r, const TrialContext& ctx);

  std::string name_;
  std::unique_ptr<transfer::TransferSystem> transfer_;
  std::unique_ptr<ActuatorSetup> setup_;
  transfer::SafetyGateGroup gate_;
  std::optional<SlotLimits> slot_limits_;
  std::vector<Exchange> last_;
  std::vector<transfer::GatedMove> moves_;
  std::vector<double> commands_, zeros_;
  Eigen::VectorXd f_;
  std::optional<Eigen::MatrixXd> k0_;
  std::optional<double> k0_ramp_;
  long evaluations_ = 0;
  bool active_ = false;
  bool held_ = false;
};

}  // namespace hybridtest::substructures
