#pragma once
// A physical substructure: a specimen on a test bench, reached through a TransferSystem and a
// SetupTransform, guarded by a SafetyGate (transfer/safety_gate.h). Every trial:
//   1. command = setup(d) [m];
//   2. the gate checks it (stroke, increment, predicted force, finite; a command beyond a limit
//      is never sent), the transfer system executes it (bench units), and the gate checks the
//      measurement (finite, hard force limit);
//   3. r^s = setup⁻¹(measured force).
// The K0 ramp and the resume moves go through the same gate.
// On any violation or communication failure the transfer system is put on Hold() (it stays at
// the last safe command) and the error propagates to the runner.
#include <functional>
#include <memory>
#include <optional>

#include "hybridtest/substructures/setup_transform.h"
#include "hybridtest/substructures/substructure.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/safety_gate.h"

namespace hybridtest::substructures {

class PhysicalSubstructure final : public Substructure {
 public:
  // The test starts with the actuator at setup.p0 (the specimen unloaded): the monitor checks
  // the first command's increment from there. `initial_stiffness` [N/m], if given, lets the
  // monitor predict forces before two measurements exist.
  PhysicalSubstructure(std::string name, std::unique_ptr<transfer::TransferSystem> transfer,
                       SetupTransform setup, transfer::SafetyLimits limits,
                       std::optional<double> initial_stiffness = std::nullopt);
  ~PhysicalSubstructure() override;

  void Activate() override;
  double Trial(double displacement, const TrialContext& context) override;
  void Commit() override {}
  void Hold() noexcept override;
  void Deactivate() override;
  bool is_physical() const override { return true; }
  Exchange last_exchange() const override { return last_; }
  long evaluations() const override { return evaluations_; }
  const transfer::TransferSystem* transfer_system() const override { return transfer_.get(); }
  std::optional<double> actuator_p0(int /*k*/) const override { return setup_.p0; }
  std::optional<transfer::SafetyLimits> actuator_limits(int /*k*/) const override {
    return gate_.monitor().limits();
  }
  SiReading ActuatorSi(int /*k*/, const transfer::Measurement& m,
                       const transfer::BenchUnits& units) const override {
    return {setup_.PositionMetres(m.position, units), setup_.ForceNewtons(m.force, units)};
  }
  transfer::TransferSystem* transfer_system() override { return transfer_.get(); }
  std::string Describe() const override;
  const transfer::SafetyMonitor& safety() const { return gate_.monitor(); }
  const transfer::TransferSystem& transfer() const { return *transfer_; }
  // For a look without moving (TransferSystem::Probe, `hybridtest probe`).
  transfer::TransferSystem& transfer() { return *transfer_; }
  // Resume: see TransferSystem::NoteCommandsBeforeResume.
  void NoteCommandsBeforeResume(long count) { transfer_->NoteCommandsBeforeResume(count); }
  const SetupTransform& setup() const { return setup_; }

  // K0 = dr/dd of the slot [N/m]: set from the config, or measured by
  // MeasureInitialStiffness(); else derived from the safety section's specimen stiffness.
  std::optional<double> initial_stiffness() const override;
  void SetInitialStiffness(double k0);
  // Measures K0 on the specimen before the test (after Activate(), before the first trial):
  // a slow ramp of `steps` equal moves from d = 0 to d = amplitude and `steps` moves back to
  // d = 0 (command p0), every move inside the safety limits (each increment is at most half
  // the monitor's max_increment), then K0 = the least-squares slope of r against d over all
  // samples. Each move is a specimen evaluation (counted, lab time). amplitude [m] > 0.
  // Returns the record {k0, amplitude, samples: [[d, r], ...]}. Throws SafetyStop,
  // TransferError, or hybridtest::Error if the slope is not positive and finite.
  struct StiffnessMeasurement {
    double k0 = 0.0;                          // [N/m]
    double amplitude = 0.0;                   // [m]
    std::vector<std::pair<double, double>> samples;  // (d [m], r [N])
  };
  StiffnessMeasurement MeasureInitialStiffness(double amplitude);
  // The config asks for K0 to be measured before the test with this ramp amplitude [m].
  void RequestStiffnessMeasurement(double amplitude) { k0_ramp_ = amplitude; }
  std::optional<double> requested_stiffness_ramp() const { return k0_ramp_; }
  // |max_increment| of the safety limits in slot displacement [m].
  double max_displacement_increment() const override;

  // Checkpoint: {"last": last exchange, "evaluations", "k0", "safety": monitor state,
  // "transfer": the in-process bench's state or null (a remote bench keeps its own)}.
  nlohmann::json SaveState() const override;
  void RestoreState(const nlohmann::json& state) override;
  // The ramp of RequestStiffnessMeasurement, if asked (MeasureInitialStiffness), else K0 as
  // configured.
  void MeasureRequestedStiffness(nlohmann::json& entry) override;
  // ReimposeCommitted, recorded.
  nlohmann::json ReimposeForResume(const ResumeRequest& request) override;

  // What a resume did on this slot (see ReimposeCommitted).
  struct ResumeCheck {
    double command = 0.0;            // the last committed command [m]
    double committed_position = 0.0; // its measured position in the journal [m]
    double committed_force = 0.0;    // its force in the journal [N]
    std::optional<double> read_position;  // bench position read before moving [m]
    std::optional<double> read_force;     // bench force read before moving [N]
    int ramp_moves = 0;              // moves before the re-imposition (bench had moved)
    double position = 0.0;           // measured after the re-imposition [m]
    double force = 0.0;              // measured after the re-imposition [N]
    double position_tolerance = 0.0; // accepted |position − committed_position| [m]
    double tolerance = 0.0;          // accepted |force − committed_force| [N]
  };
  // After RestoreState on an activated substructure, at the start of a resumed run: reads the
  // bench if it can be read without moving, and from then on checks every move against the
  // MEASURED position; if it is more than max_increment from the last committed command, ramps
  // to it in equal moves strictly within max_increment; then re-imposes the last committed
  // command (every move checked by the safety monitor: nothing outside the limits is sent) and
  // compares the measured position and force with the committed ones. `on_move` is called
  // after every exchange (last_exchange() holds it) with false for a ramp move and true for
  // the re-imposition.
  // position_tolerance [m] ≤ 0: DefaultResumePositionTolerance(); force_tolerance [N] ≤ 0:
  // DefaultResumeForceTolerance(). Throws SafetyStop (limit "resume_position_tolerance" or
  // "resume_force_tolerance", both values named) if either differs by more, after putting the
  // bench on hold; SafetyStop/TransferError from the moves.
  ResumeCheck ReimposeCommitted(double force_tolerance, double position_tolerance, long step,
                                const std::function<void(bool reimposition)>& on_move);
  // A quarter of max_increment [m].
  double DefaultResumePositionTolerance() const;
  // The smaller of 1 % of force_hard and K0 × position_tolerance (K0 of this slot, if known)
  // [N]: a force check never accepts what the position check would refuse.
  double DefaultResumeForceTolerance(double position_tolerance) const;

 private:
  std::string name_;
  std::unique_ptr<transfer::TransferSystem> transfer_;
  SetupTransform setup_;
  transfer::SafetyGate gate_;
  Exchange last_;
  std::optional<double> k0_;            // dr/dd [N/m]
  std::optional<double> k0_ramp_;       // measure K0 before the test with this amplitude [m]
  std::optional<double> safety_stiffness_;  // the safety section's specimen stiffness [N/m]
  long evaluations_ = 0;
  bool active_ = false;
  bool held_ = false;  // Hold() already sent since the last trial

  // One move through the gate: last_ and evaluations_ follow the bench's answer (also when
  // its check throws); on any failure the bench is put on hold and the error propagates.
  void GatedMoveTo(double command, transfer::MoveLabel label);
  transfer::GatedMove move_;  // the last move (reused: no allocation per trial)
};

}  // namespace hybridtest::substructures
