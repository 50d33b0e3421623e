#pragma once
// PhysicalSubstructure: a specimen moved by n actuators that serves m slots of the model (one
// slot on one actuator, a blade tip in flap and edge on two, ...), reached through one
// TransferSystem of n actuators, seen through a setup (actuator_setup.h) and guarded by one
// safety gate over the n actuators (transfer/safety_gate.h). Every trial:
//   1. the slot displacements d (m) [m] are checked against the slot limits, if any
//      (slot_limits.h), and become actuator commands a = setup(d) (n) [m]:
//        linear              a = p0 + T d            (one actuator: p0 + sign · scale · d)
//        large_displacement  a = p0 + ℓ(d) − L0
//   2. the gate checks every command (stroke, increment, predicted force, finite) BEFORE any
//      actuator moves (a refused command means none is sent), the transfer system executes all
//      n at once (bench units), and the gate checks every measurement (finite, force_hard);
//   3. r = J(d)ᵀ f (m) [N] from the measured forces f (n) after the load-cell zeros
//      (one actuator: force_sign · force_scale · f), checked against the slot force limits.
// The K0 ramp and the resume moves go through the same gate. On any violation or
// communication failure the transfer system is put on hold (every actuator) and the error
// propagates to the runner.
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "hybridtest/substructures/actuator_setup.h"
#include "hybridtest/substructures/linear_setup.h"
#include "hybridtest/substructures/setup_transform.h"
#include "hybridtest/substructures/slot_limits.h"
#include "hybridtest/substructures/substructure.h"
#include "hybridtest/transfer/safety_gate.h"

namespace hybridtest::substructures {

class PhysicalSubstructure final : public Substructure {
 public:
  // limits: one set per actuator. The test starts with every actuator at its p0 (the specimen
  // unloaded): the gate checks the first command's increment from there. Throws ConfigError if
  // the setup, the limits and the transfer system's actuators do not fit together.
  PhysicalSubstructure(std::string name, std::unique_ptr<transfer::TransferSystem> transfer,
                       std::unique_ptr<ActuatorSetup> setup,
                       std::vector<transfer::SafetyLimits> limits);
  // A linear setup a = p0 + T d of n actuators.
  PhysicalSubstructure(std::string name, std::unique_ptr<transfer::TransferSystem> transfer,
                       LinearSetup setup, std::vector<transfer::SafetyLimits> limits);
  // One actuator, one slot (`setup: {p0, sign, scale, ...}`, OneActuatorSetup). `safety_stiffness`
  // [N/m], if given, is the specimen's stiffness per actuator displacement: see
  // SetSafetyStiffness.
  PhysicalSubstructure(std::string name, std::unique_ptr<transfer::TransferSystem> transfer,
                       const SetupTransform& setup, transfer::SafetyLimits limits,
                       std::optional<double> safety_stiffness = std::nullopt);
  ~PhysicalSubstructure() override;

  void Activate() override;
  int num_slots() const override { return setup_->num_slots(); }
  void Trial(std::span<const double> d, std::span<double> r, const TrialContext& context) override;
  void Commit() override {}
  void Propose(std::span<const double> d, const TrialContext& context) override;
  void AwaitVerdict() override;
  void Release() override;
  void Hold() noexcept override;
  void Deactivate() override;
  bool is_physical() const override { return true; }
  int num_actuators() const override { return setup_->num_actuators(); }
  Exchange actuator_exchange(int k) const override { return last_[static_cast<std::size_t>(k)]; }
  long evaluations() const override { return evaluations_; }
  const transfer::TransferSystem* transfer_system() const override { return transfer_.get(); }
  transfer::TransferSystem* transfer_system() override { return transfer_.get(); }
  const ActuatorSetup* actuator_setup() const override { return setup_.get(); }
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
  // K0 (m × m) [N/m]: set from the config, measured by the ramp, else derived from the safety
  // section's specimen stiffness (SetSafetyStiffness); nullopt if none is known.
  std::optional<Eigen::MatrixXd> initial_stiffness() const override;
  // The largest change of every slot displacement that keeps every actuator's command step
  // within its max_increment, at any d: min_k max_increment_k / B_k [m], with B_k the setup's
  // CommandStepBound (Σ_i |T_ki| for a linear setup, scale for one actuator).
  double max_displacement_increment() const override;
  // Checkpoint: {"last": [[command, position, force, lab_time] per actuator], "evaluations",
  // "k0": rows or null, "safety": [monitor state per actuator], "actuator_k": rows or null,
  // "transfer": the in-process bench's state or null}. RestoreState also reads the state of a
  // one-actuator run saved before the two widths were one ({"last": {"command_m", ...},
  // "k0": number or null, "safety": one monitor state}).
  nlohmann::json SaveState() const override;
  void RestoreState(const nlohmann::json& state) override;
  // K0 measured by the ramp (if asked), configured or unknown; for several actuators or slots
  // also the setup it is seen through.
  void MeasureRequestedStiffness(nlohmann::json& entry) override;
  // ReimposeCommitted, one record per actuator (named `name` for one actuator, "NAME_aK" for
  // several).
  nlohmann::json ReimposeForResume(const ResumeRequest& request) override;
  // The start check (substructure.h; physical_start.cc), through the same reading and walk
  // as a resume (ReadPositions, WalkTo).
  nlohmann::json CheckStart(const StartRequest& request) override;

  const ActuatorSetup& setup() const { return *setup_; }
  // Limits per slot (max_displacement [m], max_force [N]), checked on every trial. Throws
  // ConfigError unless each list has one positive value per slot (+inf: none).
  void SetSlotLimits(SlotLimits limits);
  const std::optional<SlotLimits>& slot_limits() const { return slot_limits_; }
  const transfer::SafetyGate& safety() const { return gate_; }
  transfer::TransferSystem& transfer() { return *transfer_; }
  const transfer::TransferSystem& transfer() const { return *transfer_; }

  // K0 = dr/dd (m × m) [N/m]; the gate predicts the actuator forces with K_a =
  // setup().ActuatorStiffness(K0) (one actuator: its monitor's initial stiffness, if positive;
  // several: the coupled prediction). Throws ConfigError unless finite and m × m.
  void SetInitialStiffness(const Eigen::MatrixXd& k0);
  // The safety section's specimen stiffness per actuator displacement [N/m]: every monitor
  // predicts forces with it before two measurements exist, and K0 = setup().SlotStiffness(k I)
  // where no K0 is configured or measured.
  void SetSafetyStiffness(double actuator_stiffness);

  // Measures K0 before the test (after Activate(), before the first trial); every move is a
  // specimen evaluation through the gate (counted, lab time), labelled step −1.
  //   one actuator and one slot: a slow ramp of `steps` equal moves from d = 0 to
  //     d = amplitude and back to d = 0, each increment at most half the largest allowed
  //     (max_displacement_increment), at least 4 up and 4 down; K0 = the least-squares slope
  //     of r against d over all samples (samples: (d, r));
  //   otherwise: each actuator in turn ramps from p0 to p0 + amplitude and back in equal moves
  //     (each at most half its max_increment; the others stay at p0); the symmetric actuator
  //     stiffness K_a (n × n) is fitted by least squares to all samples (samples: (a − p0, f)),
  //     and K0 = T0ᵀ K_a T0 with T0 = J(0) (exact at d = 0: the setup's geometric stiffness
  //     vanishes at zero force).
  // amplitude [m] > 0. Throws SafetyStop, TransferError, or hybridtest::Error if K0 is not
  // positive (its diagonal) and finite.
  struct StiffnessMeasurement {
    Eigen::MatrixXd k0;            // m × m [N/m]
    Eigen::MatrixXd actuator_k;    // n × n [N/m]
    double amplitude = 0.0;        // [m]
    std::vector<std::pair<Eigen::VectorXd, Eigen::VectorXd>> samples;  // see above
  };
  StiffnessMeasurement MeasureInitialStiffness(double amplitude);
  // The config asks for K0 to be measured before the test with this ramp amplitude [m].
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
  // Resume (physical_resume.cc), after RestoreState on an activated substructure: if the
  // transfer system can read every actuator without moving (TransferSystem::ReadAll), every
  // monitor starts from the MEASURED positions, and if an actuator is more than its
  // max_increment from its committed command, all actuators walk back together in equal moves
  // strictly within every max_increment; then every committed command is re-imposed at once
  // (all checked before any moves). Each actuator's measured position and force are compared
  // with the committed ones within position_tolerance [m] (≤ 0: a quarter of its
  // max_increment) and force_tolerance [N] (≤ 0: the smaller of 1 % of its force_hard and
  // K_a,kk times its position tolerance, when K_a is known). Beyond either, every actuator
  // holds and SafetyStop (limit "resume_position_tolerance" or "resume_force_tolerance") names
  // the actuator. on_move(false) after each ramp move, on_move(true) after the re-imposition.
  ResumeCheck ReimposeCommitted(double force_tolerance, double position_tolerance, long step,
                                const std::function<void(bool reimposition)>& on_move);
  // The defaults of actuator k (0-based): a quarter of its max_increment [m], and the smaller
  // of 1 % of its force_hard and K_a,kk × position_tolerance [N] (K_a: what the gate predicts
  // this actuator's force with, from K0 or the safety section's specimen stiffness, if known):
  // a force check never accepts what the position check would refuse.
  double DefaultResumePositionTolerance(int k = 0) const;
  double DefaultResumeForceTolerance(double position_tolerance, int k = 0) const;

 private:
  // One move of every actuator through the gate: last_ and evaluations_ follow the bench's
  // answer (also when its check throws); on any failure the bench holds and the error
  // propagates.
  void MoveAll(const std::vector<double>& commands, transfer::MoveLabel label);
  // The one reading of where every actuator is before a run or a resume moves it
  // (physical_start.cc): every position [m] (and force [N], after the load-cell zeros, into
  // `forces` if given) read without moving (TransferSystem::ReadAll), and every monitor then
  // checks the next move from there (SetStartPosition); nullopt if the transfer system cannot
  // read every actuator so.
  std::optional<std::vector<double>> ReadPositions(std::vector<double>* forces = nullptr);
  // The one walk from `from` to `to` (n) [m]: every actuator together, in equal moves strictly
  // within every max_increment (ResumeMoves), each through the gate, on_move() after each; the
  // move onto `to` itself is left to the caller. Returns the moves made.
  int WalkTo(const std::vector<double>& from, const std::vector<double>& to, long step,
             const std::function<void()>& on_move);
  // Throws SafetyStop (after holding) if a slot displacement (before) or force (after) is
  // beyond its slot limit.
  void CheckSlotDisplacements(std::span<const double> d, const TrialContext& ctx);
  void CheckSlotForces(std::span<const double> r, const TrialContext& ctx);
  // K_a (n × n) [N/m] for the gate: see SetInitialStiffness.
  void UseActuatorStiffness(const Eigen::MatrixXd& actuator_k);
  StiffnessMeasurement MeasureSlotRamp(double amplitude);
  StiffnessMeasurement MeasureActuatorRamps(double amplitude);

  std::string name_;
  std::unique_ptr<transfer::TransferSystem> transfer_;
  std::unique_ptr<ActuatorSetup> setup_;
  transfer::SafetyGate gate_;
  std::optional<SlotLimits> slot_limits_;
  std::vector<Exchange> last_;               // (n)
  std::vector<transfer::GatedMove> moves_;   // (n), reused: no allocation per trial
  std::vector<double> commands_, zeros_;     // (n) [m], [N]
  std::vector<double> proposed_;             // (n) [bench length unit], the last Propose
  Eigen::VectorXd f_;                        // (n) [N]
  std::optional<Eigen::MatrixXd> k0_;        // (m × m) [N/m]
  std::optional<Eigen::MatrixXd> actuator_k_;  // (n × n) [N/m], what the gate predicts with
  std::optional<double> safety_stiffness_;   // [N/m] per actuator displacement
  std::optional<double> k0_ramp_;            // [m]
  long evaluations_ = 0;
  bool active_ = false;
  bool held_ = false;  // Hold() already sent since the last move
};

}  // namespace hybridtest::substructures
