#pragma once
// SubstructureSpec: what owns one restoring-force slot, as data. Compiled once (from a run
// config by io/run_spec_yaml.h, or written directly in C++), then built as often as needed:
// every Build() makes a fresh substructure with nothing activated or connected (a `plan`
// builds one per candidate, a resume one per session). Building never writes into the spec.
//
//   numerical: a restoring-force law (a prototype, cloned by every Build());
//   custom:    a factory of any Substructure (a program's own);
//   physical:  a transfer system (a factory of the configured type), the setup (one actuator's
//              SetupTransform, a linear setup of n actuators or another geometry), the safety
//              limits and how K0 is known (given, measured by a ramp, or predicted from the
//              safety section's specimen stiffness). Every size builds a PhysicalSubstructure.
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>
#include <vector>

#include "hybridtest/constitutive/restoring_force_law.h"
#include "hybridtest/constitutive/vector_law.h"
#include "hybridtest/substructures/actuator_setup.h"
#include "hybridtest/substructures/linear_setup.h"
#include "hybridtest/substructures/slot_limits.h"
#include "hybridtest/substructures/setup_transform.h"
#include "hybridtest/substructures/substructure.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::substructures {

// The name of actuator k (0-based) of n of the substructure `name`, as its journal channels and
// records name it: `name` itself for one actuator, "<name>_a<k+1>" for several.
std::string ActuatorName(const std::string& name, int k, int n);

// A transfer system of one configured type, ready to be made (nothing connected yet).
struct TransferSpec {
  std::string type;  // "emulated", "loopback", "remote", "modbus", "openfresco", or a user's
  std::function<std::unique_ptr<transfer::TransferSystem>()> make;
};

struct PhysicalSpec {
  TransferSpec transfer;
  SetupTransform setup;
  transfer::SafetyLimits limits;
  // safety.initial_stiffness: the specimen's expected stiffness per actuator displacement,
  // for the monitor's force prediction. Unit: [N/m].
  std::optional<double> safety_stiffness;
  // K0 = dr/dd given in the config. Unit: [N/m] (or [N·m/rad]).
  std::optional<double> initial_stiffness;
  // Measure K0 before the test with a ramp of this amplitude. Unit: [m].
  std::optional<double> stiffness_ramp;
  // Several actuators (`setup: transform`): the linear setup, and the limits of each actuator
  // (`limits` then holds actuator 1's). Unset: one actuator with `setup`.
  std::optional<LinearSetup> linear;
  std::vector<transfer::SafetyLimits> actuator_limits;
  // K0 = dr/dd given as an m × m matrix. Unit: [N/m].
  std::optional<Eigen::MatrixXd> initial_stiffness_matrix;
  // Several actuators with another setup than `linear` (`setup: {geometry:
  // large_displacement, ...}`: a RodSetup); used when `linear` is unset.
  std::shared_ptr<const ActuatorSetup> actuator_setup;
  // Several actuators: limits per slot (`safety: {slots: {...}}`); names filled by Build().
  std::optional<SlotLimits> slot_limits;
};

struct SubstructureSpec {
  // The model's slot name; for a substructure of several slots, its own name (the config's
  // key), which names its journal channels.
  std::string slot;
  // The slots served, in order (`slots:`); empty: the one slot `slot`.
  std::vector<std::string> slots;
  // Numerical, several slots: r = K d with this m × m stiffness [N/m] (then `law` is empty).
  std::optional<Eigen::MatrixXd> stiffness;
  // Numerical, several slots: r = Tᵀ F(T d) with this coupled law of n axes (a prototype) and
  // T = block_transform (n × m; unset: the identity). See law_block.h.
  std::shared_ptr<const constitutive::VectorRestoringForceLaw> block_law;
  std::optional<Eigen::MatrixXd> block_transform;
  // Numerical, several slots: block_law seen through this setup instead of T,
  // r = J(d)ᵀ F(a(d) − p0) (law_block.h); the twin of a large-displacement setup.
  std::shared_ptr<const ActuatorSetup> block_setup;
  // Numerical: the law (a prototype; never trialled itself).
  std::shared_ptr<const constitutive::RestoringForceLaw> law;
  // Physical (then `law` is empty).
  std::optional<PhysicalSpec> physical;
  // Any other substructure (a program's own, a test's fake): made by this factory, which must
  // return a fresh one each time. `custom_is_physical`: it moves a bench (journal channels,
  // syncing every row).
  std::function<std::unique_ptr<Substructure>()> custom;
  bool custom_is_physical = false;

  bool is_physical() const { return physical.has_value() || (custom && custom_is_physical); }
  // The slots served, in order.
  std::vector<std::string> SlotNames() const { return slots.empty() ? std::vector{slot} : slots; }
  // Actuators moved: 0 numerical, n for a setup of several actuators, else 1.
  int num_actuators() const {
    if (!is_physical()) return 0;
    if (physical && physical->linear) return physical->linear->num_actuators();
    if (physical && physical->actuator_setup) return physical->actuator_setup->num_actuators();
    return 1;
  }
  // The names of its actuators' journal channels, in actuator order: the slot's name for one
  // actuator, "<name>_a1", "<name>_a2", ... for several (ActuatorName); empty if numerical.
  std::vector<std::string> ActuatorNames() const;
  // Each actuator's safety limits (SI), in actuator order; empty if not `physical`.
  std::vector<transfer::SafetyLimits> ActuatorLimits() const;
  // A fresh substructure. Throws ConfigError if the spec is empty or inconsistent, and what
  // the transfer factory throws.
  std::unique_ptr<Substructure> Build() const;
};

// For each spec, the indices (into model_slots) of the slots it serves, in its order. Throws
// ConfigError unless every model slot is served by exactly one spec.
std::vector<std::vector<int>> SlotIndices(const std::vector<SubstructureSpec>& specs,
                                          const std::vector<std::string>& model_slots);

// The numerical twin of a substructure on an emulated bench of several actuators whose
// specimen law and setup it can see (a PhysicalSubstructure on a coupled EmulatedBench, the
// setup's p0 equal to the bench's, no load-cell zero): a spec with block_law and
// block_transform = the setup's T (linear) or block_setup = the setup (any other geometry).
// nullopt for anything else.
std::optional<SubstructureSpec> EmulatedBlockTwin(const Substructure& s);

// A numerical slot of law `law`.
SubstructureSpec NumericalSpec(std::string slot, std::unique_ptr<constitutive::RestoringForceLaw> law);

}  // namespace hybridtest::substructures
