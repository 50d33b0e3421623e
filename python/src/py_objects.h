#pragma once
// Python objects behind the C++ seams, so that the runner treats them as its own:
//
//   PyTransfer  a Python bench driver as a transfer::TransferSystem. The object has
//               activate(), execute(command) -> (position, force[, lab_time]), hold() and
//               deactivate(); it speaks SI (m, N) unless it has `units = ("mm", "kN")`
//               (length m | mm, force N | kN). Without a lab_time [s], the wall time since
//               activate() is recorded.
//               A specimen on n > 1 actuators: execute(commands) receives a numpy array of
//               n commands (a fresh copy, actuator order) and returns (positions, forces[,
//               lab_time]), two sequences of n numbers; `p0`, `settle_tolerance` and
//               `following_error` may then be lists of n (a number applies to every one).
//               A driver with an attribute `actuators` is refused, before anything is
//               activated, unless it equals the specimen's number of actuators. The PhysicalSubstructure around it applies the setup
//               transform, the safety gate, the journal, the run state and resume exactly as
//               for a C++ transfer system. An exception raised by the Python code (or a reply
//               that is not two or three numbers) becomes a TransferError naming the slot and
//               the command: the run holds.
//               Like a Modbus controller, a driver reports a settled move: every reply goes
//               through the same SettledReadingCheck (transfer/safety_settled_reading.h):
//               |command − position| ≤ following_error, and no stale reply (the previous
//               position, bit for bit, after a command that moved by more than two settling
//               windows). The driver may give `settle_tolerance` and `following_error` (its
//               length unit); defaults 0.05 mm and four settling windows, at most the slot's
//               safety.max_increment. A violation is a SafetyStop: the run holds.
//               execute() runs on a thread of its own (bounded_call.h) and the run waits for
//               it at most the slot's safety.timeout [s]: a call that has not returned by then
//               is a TransferError naming the call and the timeout, the run stops and the bench
//               is told to hold (hold() is called, while execute() may still be running: a
//               Python call cannot be stopped; it is abandoned, its reply dropped, and a later
//               execute() on this driver is refused while it runs). A hold() or deactivate()
//               that needs the GIL waits for an abandoned call that holds it (one stuck in C
//               code); one in time.sleep() or Python code lets them run. Ctrl-C while waiting
//               stops the run as below, even when the call is stuck. KeyboardInterrupt (or another BaseException that is not
//               an Exception, e.g. SystemExit) raised inside execute() stops the run as a
//               hold (runner::Interrupted) and reaches the Python caller as itself, untouched
//               (KeepForCaller below).
//               A driver that knows its actuator's zero-force position has `p0` (its length
//               unit): the run then refuses a setup.p0 that disagrees, before anything moves
//               (runner/pre_move_checks.h).
//   PyLaw       a Python callable r = law(d) [m] -> [N] as a constitutive::RestoringForceLaw
//               (a numerical substructure). Optional attributes: commit() (a path-dependent
//               law), initial_stiffness [N/m] (else a central difference at d = 0).
//
// The C++ run loop runs without the GIL; every call into Python takes it here.
#include <pybind11/pybind11.h>

#include <chrono>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/constitutive/restoring_force_law.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/safety_settled_reading.h"
#include "hybridtest/transfer/transfer_system.h"

#include "bounded_call.h"

namespace hybridtest::python {

namespace py = pybind11;

// Re-entry: the bench driver's call the run is inside now on this thread (GIL held);
// CurrentCallback() is nullptr outside any. PySession refuses a call that changes the run (step, run, close, ...)
// from inside one, naming it. Cheap: nothing is formatted unless asked.
class InCallback {  // sets CurrentCallback() for its scope (GIL held)
 public:
  InCallback(const char* method, const std::string& slot, const std::string& unit,
             std::span<const double> commands = {});
  ~InCallback();
  InCallback(const InCallback&) = delete;
  InCallback& operator=(const InCallback&) = delete;
  std::string Call() const;      // "execute(21.3 mm)", "execute([20, 31.2] mm)", "hold()"
  std::string Describe() const;  // "the bench driver's execute(0.0213 m) of slot r1"

 private:
  const char* method_;
  const std::string& slot_;
  const std::string& unit_;
  std::span<const double> commands_;  // (bench units) empty: not execute()
  const InCallback* previous_;
};
const InCallback* CurrentCallback();

// A Python exception raised inside a callback that must reach the Python caller as itself,
// not as a TransferError around it (KeyboardInterrupt, SystemExit, a refused re-entry): kept
// here (GIL held) while the C++ run stops, then raised by PySession once the step returns.
// The first one kept wins.
void KeepForCaller(py::error_already_set error);
std::optional<py::error_already_set> TakeKeptForCaller();

// In the catch of a Python exception raised by any callback (a driver, a law, an observer): a
// BaseException that is not an Exception (KeyboardInterrupt, SystemExit) is kept for the
// caller (KeepForCaller) and stops the run as runner::Interrupted("<type> inside <where>:
// <consequence>"), so that the run holds after the step in progress, every committed row is
// kept, and the caller gets the exception as itself; any other exception is returned,
// described, for the callback's own error.
std::string InterruptOrDescribe(py::error_already_set& e, const std::string& where,
                                const std::string& consequence);

// A Python object that may be copied and dropped without the GIL (the last owner takes it).
class SharedObject {
 public:
  explicit SharedObject(py::object object);  // GIL held
  ~SharedObject();
  SharedObject(const SharedObject&) = delete;
  SharedObject& operator=(const SharedObject&) = delete;
  const py::object& get() const { return object_; }

 private:
  py::object object_;
};
using SharedPy = std::shared_ptr<SharedObject>;

// The exception a session's bench driver raised last (the exception object, with its
// traceback), so that the TransferError the run stops with carries it as __cause__. One per
// session, shared with its drivers; read and written with the GIL held.
struct DriverCause {
  SharedPy exception;  // nullptr: none
};
using DriverCauseSlot = std::shared_ptr<DriverCause>;

class PyTransfer final : public transfer::TransferSystem {
 public:
  // Reads `units`, `p0`, `settle_tolerance` and `following_error` (GIL held). `limits` are
  // each actuator's (SI; one per actuator: their number is the driver's): safety.timeout
  // bounds every execute(), max_increment caps the default following error. Throws ConfigError
  // for units it does not know, a missing method or a bad attribute.
  // `cause` (may be null) keeps the exception a driver call raises.
  PyTransfer(SharedPy driver, std::string slot, std::vector<transfer::SafetyLimits> limits,
             DriverCauseSlot cause = nullptr);
  PyTransfer(const PyTransfer&) = delete;  // reply_source_ refers to this object
  PyTransfer& operator=(const PyTransfer&) = delete;
  void Activate() override;
  // The driver's execute(command) with the command(s) in its length unit.
  int num_actuators() const override { return static_cast<int>(n_); }
  void Execute(std::span<const double> commands, std::span<transfer::Measurement> out) override;
  void Hold() noexcept override;
  void Deactivate() override;
  transfer::BenchUnits bench_units() const override { return units_; }
  transfer::BenchAnnouncement Announce() const override;
  std::string Describe() const override { return description_; }
  // The driver's optional read(), without moving: the same reply as execute()'s (positions
  // and forces in its units); nullopt if it has none, raises, or replies otherwise (the start
  // check then records that it could not read). Never throws.
  std::optional<std::vector<transfer::Measurement>> ReadAll() override;

 private:
  void Call(const char* method, const std::string& what);
  // The driver's reply to execute(): n positions and forces, and the lab time if given. Throws
  // py::cast_error or sets `problem` (GIL held).
  static bool ReadReply(const py::object& reply, std::size_t n,
                        std::span<transfer::Measurement> out, std::string& problem);
  std::string ExecuteText(std::span<const double> commands) const;  // "execute(21.3 mm)"
  void KeepCause(const py::error_already_set& e);  // GIL held
  SharedPy driver_;
  std::string slot_;
  std::size_t n_;  // actuators
  DriverCauseSlot cause_;
  std::string description_;
  transfer::BenchUnits units_;
  std::vector<double> p0_;    // the driver's `p0`, one per actuator (empty: none) [m]
  double timeout_;            // the slot's safety.timeout [s] (the shortest of the actuators')
  transfer::SettledReadingCheck settled_;  // following error and stale reply (bench units)
  transfer::SettledReadingCheck::Source reply_source_;  // how its messages name this driver
  std::span<const double> commands_now_;  // the commands being checked (bench units)
  std::vector<double> positions_;         // scratch: the reply's positions (bench units)
  std::vector<double> forces_;            // its reply's forces (bench units)
  std::chrono::steady_clock::time_point activated_;
  BoundedCall execute_call_;  // last: its destructor runs first (joins or detaches the worker)
};

class PyLaw final : public constitutive::RestoringForceLaw {
 public:
  PyLaw(SharedPy law, std::string slot);  // GIL held: reads initial_stiffness
  double Trial(double displacement) override;
  void Commit() override;
  double initial_stiffness() const override { return k0_; }
  std::unique_ptr<constitutive::RestoringForceLaw> Clone() const override {
    return std::make_unique<PyLaw>(*this);
  }
  std::string Describe() const override { return description_; }

 private:
  double Evaluate(double displacement) const;  // GIL held
  SharedPy law_;
  std::string slot_;
  std::string description_;
  double k0_ = 0.0;
};

}  // namespace hybridtest::python
