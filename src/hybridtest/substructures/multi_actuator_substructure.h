#pragma once
// MultiActuatorSubstructure: a specimen moved by n actuators that serves m slots of the model
// (a blade tip in flap and edge), reached through one TransferSystem of n actuators, a setup
// (actuator_setup.h: linear, a = p0 + T d and r = Tᵀ f, or large-displacement, a = p0 + ℓ(d)
// − L0 and r = J(d)ᵀ f) and a SafetyGateGroup (one monitor per actuator, every command
// checked before any actuator moves), with optional limits per slot (slot_limits.h). On any
// violation or communication failure the transfer system holds (every actuator) and the error
// propagates.
#include <functional>
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
  const transfer::TransferSystem* transfer_system() const override { return transfer_.get(); }
  transfer::TransferSystem* transfer_system() override { return transfer_.get(); }
  std::optional<double> actuator_p0(int k) const override { return setup_->p0()(k); }
  std::optional<transfer::SafetyLimits> actuator_limits(int k) const override {
    return gate_.monitor(k).limits();
  }
  SiReading ActuatorSi(int k, const transfer::Measurement& m,
                       const transfer::BenchUnits& units) const override {
    return {m.position * units.metres_per_length_unit,
            m.force * units.newtons_per_force_unit - setup_->load_cell_zero()(k)};
  }
  std::string Describe() const override;
  std::optional<double> initial_stiffness() const override;
  std::optional<Eigen::MatrixXd> initial_stiffness_matrix() const override { return k0_; }
  // The largest change of every slot displacement that keeps every actuator's command step
  // within its max_increment, at any d: min_k max_increment_k / B_k [m], with B_k the setup's
  // CommandStepBound (Σ_i |T_ki| for a linear setup).
  double max_displacement_increment() const override;
  nlohmann::json SaveState() const override;
  void RestoreState(const nlohmann::json& state) override;
  // K0 (m × m) measured by the ramp, configured or unknown, and the setup it is seen through.
  void MeasureRequestedStiffness(nlohmann::json& entry) override;
  // ReimposeCommitted, one record per actuator ("NAME_aK").
  nlohmann::json ReimposeForResume(const ResumeRequest& request) override;

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

  // What a resume did on each actuator (see ReimposeCommitted; recorded in the sidecar).
  struct ResumeCheck {
    struct Actuator {
      double command = 0.0;                 // the last committed command [m]
      double committed_position = 0.0;      // the journal's committed position [m]
      double committed_force = 0.0;         // the journal's committed force [N]
      std::optional<double> read_position;  // read before anything moved [m] (if it can)
      std::optional<double> read_force;     // read before anything moved [N] (if it can)
      double position = 0.0;                // measured after the re-imposition [m]
      double force = 0.0;                   // measured after the re-imposition [N]
      double position_tolerance = 0.0;      // accepted |position − committed| [m]
      double force_tolerance = 0.0;         // accepted |force − committed| [N]
    };
    std::vector<Actuator> actuators;
    int ramp_moves = 0;  // moves before the re-imposition (an actuator had moved)
  };
  // Resume (multi_actuator_resume.cc), the several-actuator form of
  // PhysicalSubstructure::ReimposeCommitted: if the transfer system can read every actuator
  // without moving (TransferSystem::ReadAll), every monitor starts from the MEASURED
  // positions, and if an actuator is more than its max_increment from its committed command,
  // all actuators walk back together in equal moves strictly within every max_increment; then
  // every committed command is re-imposed at once (all checked before any moves). Each
  // actuator's measured position and force are compared with the committed ones within
  // position_tolerance [m] (≤ 0: a quarter of its max_increment) and force_tolerance [N]
  // (≤ 0: the smaller of 1 % of its force_hard and K_a,kk times its position tolerance, when
  // the gate knows K_a). Beyond either, every actuator holds and SafetyStop (limit
  // "resume_position_tolerance" or "resume_force_tolerance") names the actuator. on_move(false)
  // after each ramp move, on_move(true) after the re-imposition.
  ResumeCheck ReimposeCommitted(double force_tolerance, double position_tolerance, long step,
                                const std::function<void(bool reimposition)>& on_move);

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
