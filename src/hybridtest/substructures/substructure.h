#pragma once
// Substructure: the owner of restoring forces r^s of the model (OpenFresco's two phases).
//   Trial(d, r)  displacements in, the static restoring forces out. Numerical: computed.
//                Physical: the actuators move (this is the one impure seam of a hybrid test).
//   Commit()     makes the last trial permanent (the state it was taken at is committed).
// A substructure knows nothing of Kane: it sees displacements d [m] and returns r^s [N].
//
// One width for every size: a substructure serves num_slots() slots (m ≥ 1) in the order its
// spec lists them; the seam calls Trial(d, r, context) with m displacements and m forces; its
// K0 is an m × m matrix; a physical one moves num_actuators() actuators (n) and reports one
// Exchange per actuator (actuator_exchange(k)). One slot or one actuator is an ordinary size.
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>

#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::substructures {

class ActuatorSetup;

// Where a trial happens, for messages and records.
struct TrialContext {
  long step = 0;     // step index n (0-based); the trial belongs to step n → n+1
  int stage = 0;     // Runge–Kutta stage (0-based)
  double t = 0.0;    // model time of the stage [s]
};

// What a physical substructure exchanged in its last trial, in SI.
struct Exchange {
  double command = 0.0;   // actuator command (absolute position) [m]
  double position = 0.0;  // measured actuator position [m]
  double force = 0.0;     // measured force, after the setup transform's zero [N]
  double lab_time = 0.0;  // bench lab time at the sample [s]
  long force_reversals = 0;  // reversals of the specimen force within the move, if seen [-]
};

class Substructure {
 public:
  virtual ~Substructure() = default;
  // Makes the substructure ready (a physical one activates its transfer system).
  virtual void Activate() {}
  // Slots served (m ≥ 1).
  virtual int num_slots() const { return 1; }
  // r (m) [N] at the slot displacements d (m) [m]. Throws TransferError or SafetyStop for a
  // physical one.
  virtual void Trial(std::span<const double> d, std::span<double> r,
                     const TrialContext& context) = 0;
  virtual void Commit() = 0;
  // The two phases of a trial when several substructures move together (docs/multi-site.md):
  // Propose checks the move Trial(d, ·, context) will make (slot limits, the safety gate's
  // command checks) WITHOUT moving and proposes it to the transfer system; AwaitVerdict
  // throws SafetyStop if the move was refused (nothing moved), TransferError if no verdict
  // came; Release lets the accepted move start; Trial(d, r, context) then collects it.
  // Numerical substructures propose nothing (the defaults).
  virtual void Propose(std::span<const double> /*d*/, const TrialContext& /*context*/) {}
  virtual void AwaitVerdict() {}
  virtual void Release() {}
  // Safe state after a failure: a physical one holds its actuator. Never throws.
  virtual void Hold() noexcept {}
  // Ends the test cleanly.
  virtual void Deactivate() {}
  virtual bool is_physical() const { return false; }
  // Actuators moved (n; 0 for a numerical substructure) and the last exchange of actuator k
  // (0-based) with the bench.
  virtual int num_actuators() const { return is_physical() ? 1 : 0; }
  virtual Exchange actuator_exchange(int /*k*/) const { return {}; }
  // The transfer system that moves this substructure's num_actuators() actuators (nullptr for a
  // numerical one): what the runner asks of it through the TransferSystem interface (can it
  // run paced, its delay, a probe, the commands it received), never its concrete type.
  virtual const transfer::TransferSystem* transfer_system() const { return nullptr; }
  virtual transfer::TransferSystem* transfer_system() { return nullptr; }
  // The setup its actuators see the slots through (actuator_setup.h; nullptr for a numerical
  // substructure or one that does not say): what `plan`'s numerical twin needs (twin.h).
  virtual const ActuatorSetup* actuator_setup() const { return nullptr; }
  // The zero-force position p0 of actuator k (0-based) [m] and its safety limits (SI), as the
  // setup and the safety section give them, for the checks against what a bench announces
  // before anything moves (runner/pre_move_checks.h); nullopt where not known.
  virtual std::optional<double> actuator_p0(int /*k*/) const { return std::nullopt; }
  virtual std::optional<transfer::SafetyLimits> actuator_limits(int /*k*/) const {
    return std::nullopt;
  }
  // A reading of actuator k in the bench's units (transfer_system()->bench_units()) as the
  // setup sees it: position [m] and force [N] after the load-cell zero (`hybridtest probe`).
  struct SiReading {
    double position = 0.0;  // [m]
    double force = 0.0;     // [N]
  };
  virtual SiReading ActuatorSi(int /*k*/, const transfer::Measurement& m,
                               const transfer::BenchUnits& units) const {
    return {m.position * units.metres_per_length_unit, m.force * units.newtons_per_force_unit};
  }
  // Number of trials sent to a bench so far (physical substructures only).
  virtual long evaluations() const { return 0; }
  virtual std::string Describe() const = 0;
  // The specimen's initial stiffness K0 = dr/dd (m × m), if known (operator-splitting
  // schemes use it). Unit: [N/m] (or [N·m/rad] for a rotational slot).
  virtual std::optional<Eigen::MatrixXd> initial_stiffness() const { return std::nullopt; }
  // The largest change of the slot displacement between two trials that the safety limits
  // allow (+inf if none). Unit: [m] (or [rad]).
  virtual double max_displacement_increment() const {
    return std::numeric_limits<double>::infinity();
  }
  // The committed state, for a run's checkpoint (runner/run_state.h): taken right after
  // Commit(), restored on a freshly built and activated substructure of the same config so
  // that the run continues as if it had not stopped. Throws hybridtest::Error if a state does
  // not fit. Default: a stateless substructure ({}). On a resume the runner adds
  // "commands_received_at_stop" (the count its transfer system's commands_received() gave when
  // the run stopped, if recorded) to the saved state it restores.
  virtual nlohmann::json SaveState() const { return nlohmann::json::object(); }
  virtual void RestoreState(const nlohmann::json& /*state*/) {}

  // Before the test (after Activate(), before the first trial): measures K0 by the ramp the
  // config asks for, if it asks, and fills `entry` (the sidecar's initial_stiffness record of
  // this substructure: k0 and its source, and what the ramp saw). Default: K0 as known
  // (a number for one slot, rows of numbers for several), source "law" ("configured" for a
  // physical one), or null and "unknown".
  virtual void MeasureRequestedStiffness(nlohmann::json& entry);

  // Resume (runner/session_resume.cc), after RestoreState on an activated substructure: brings
  // every actuator back to its last committed command and checks position and force (see
  // PhysicalSubstructure::ReimposeCommitted),
  // within force_tolerance [N] and position_tolerance [m] (≤ 0: the defaults);
  // `on_move(reimposition)` after every exchange. Returns one sidecar record per actuator,
  // named after `name` (empty for a numerical substructure). Throws SafetyStop, TransferError.
  struct ResumeRequest {
    std::string name;
    double force_tolerance = 0.0;     // [N]
    double position_tolerance = 0.0;  // [m]
    long step = 0;
    std::function<void(bool reimposition)> on_move;
  };
  virtual nlohmann::json ReimposeForResume(const ResumeRequest& /*request*/) {
    return nlohmann::json::array();
  }

  // The start check of a new run (docs/safety.md, "The start of a run"), after Activate() and
  // before any other move: every actuator's position is read through the transfer system
  // (TransferSystem::ReadAll) and compared with the first command the run will send (the
  // setup's command at `d0` (m) [m], or at d = 0 when a K0 ramp comes first). Within an
  // actuator's max_increment the run starts from there; farther, SafetyStop (limit
  // "start_position", nothing moved) unless `ramp` (`start: ramp`), which moves every actuator
  // together from where it is to that command in equal moves within every max_increment, each
  // through the safety gate (on_move() after each). Returns the sidecar's record (an object:
  // slot, read (bool), per actuator the read position, the first command, p0, and the ramp
  // moves); null for a substructure that moves nothing. Throws SafetyStop, TransferError.
  struct StartRequest {
    std::string name;
    std::span<const double> d0;  // (m) [m]
    bool ramp = false;
    std::function<void()> on_move;
  };
  virtual nlohmann::json CheckStart(const StartRequest& /*request*/) { return nullptr; }
};

// A matrix as rows of numbers, for records.
nlohmann::json MatrixJson(const Eigen::MatrixXd& m);

}  // namespace hybridtest::substructures
