#pragma once
// Python objects behind the C++ seams, so that the runner treats them as its own:
//
//   PyTransfer  a Python bench driver as a transfer::TransferSystem. The object has
//               activate(), execute(command) -> (position, force[, lab_time]), hold() and
//               deactivate(); it speaks SI (m, N) unless it has `units = ("mm", "kN")`
//               (length m | mm, force N | kN). Without a lab_time [s], the wall time since
//               activate() is recorded. The PhysicalSubstructure around it applies the setup
//               transform, the safety gate, the journal, the run state and resume exactly as
//               for a C++ transfer system. An exception raised by the Python code (or a reply
//               that is not two or three numbers) becomes a TransferError naming the slot and
//               the command: the run holds.
//               A driver that knows its actuator's zero-force position has `p0` (its length
//               unit): the run then refuses a setup.p0 that disagrees, before anything moves
//               (runner/pre_move_checks.h).
//               Several actuators (decision 0015): execute will receive an array of commands
//               and return arrays; the scalar Execute here is where that change goes.
//   PyLaw       a Python callable r = law(d) [m] -> [N] as a constitutive::RestoringForceLaw
//               (a numerical substructure). Optional attributes: commit() (a path-dependent
//               law), initial_stiffness [N/m] (else a central difference at d = 0).
//
// The C++ run loop runs without the GIL; every call into Python takes it here.
#include <pybind11/pybind11.h>

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "hybridtest/constitutive/restoring_force_law.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::python {

namespace py = pybind11;

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

class PyTransfer final : public transfer::TransferSystem {
 public:
  // Reads `units` (GIL held). Throws ConfigError for units it does not know or a missing method.
  PyTransfer(SharedPy driver, std::string slot);
  void Activate() override;
  using transfer::TransferSystem::Execute;
  transfer::Measurement Execute(double command) override;
  void Hold() noexcept override;
  void Deactivate() override;
  transfer::BenchUnits bench_units() const override { return units_; }
  transfer::BenchAnnouncement Announce() const override;
  std::string Describe() const override { return description_; }

 private:
  void Call(const char* method, const std::string& what);
  SharedPy driver_;
  std::string slot_;
  std::string description_;
  transfer::BenchUnits units_;
  std::optional<double> p0_;  // the driver's `p0` [m]
  std::chrono::steady_clock::time_point activated_;
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
