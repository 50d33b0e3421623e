#pragma once
// RestoringForceLaw: a one-dimensional static restoring-force law r = R(d), shared by the
// emulated specimens of the transfer layer and by the numerical substructures, so that no law
// is written twice.
//
// Two phases, in OpenFresco's vocabulary:
//   Trial(d)  evaluates the force at displacement d, starting from the COMMITTED state. It may
//             be called any number of times; it never changes the committed state.
//   Commit()  makes the state reached by the last Trial permanent (a path-dependent law such as
//             Bouc–Wen integrates its internal variables from the committed to the trial
//             displacement).
// Sign convention: the force is the specimen's restoring force, positive for a positive
// displacement of a spring with positive stiffness.
#include <nlohmann/json.hpp>

#include <memory>
#include <string>

namespace hybridtest::constitutive {

class RestoringForceLaw {
 public:
  virtual ~RestoringForceLaw() = default;

  // Force at `displacement` reached from the committed state. Unit: [m] -> [N].
  // Does not change the committed state.
  virtual double Trial(double displacement) = 0;

  // Makes the last trial permanent. Without a preceding Trial, it does nothing.
  virtual void Commit() = 0;

  // Tangent stiffness at the undeformed, virgin state. Unit: [N/m].
  virtual double initial_stiffness() const = 0;

  // An independent copy with the same parameters AND the same committed state.
  virtual std::unique_ptr<RestoringForceLaw> Clone() const = 0;

  // One line for logs, e.g. "linear spring k=7200 N/m".
  virtual std::string Describe() const = 0;
  // The committed state (a run's checkpoint, runner/run_state.h): a path-dependent law's
  // internal variables in SI ({} for an elastic law). RestoreState(SaveState()) on a law with
  // the same parameters continues bit-identically. RestoreState throws hybridtest::Error if
  // the state does not belong to this kind of law.
  virtual nlohmann::json SaveState() const { return nlohmann::json::object(); }
  virtual void RestoreState(const nlohmann::json& /*state*/) {}
};

}  // namespace hybridtest::constitutive
