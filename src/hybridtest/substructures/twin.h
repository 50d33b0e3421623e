#pragma once
// The numerical twin of a physical substructure on an emulated bench, for `plan`'s reference
// run (runner/plan.h) — what the builders know of the concrete bench behind a substructure, so
// that nothing above them casts:
//   TwinLaw        one actuator, one slot: the emulated specimen's law as a numerical law
//                  (through the setup where it is not the identity), else a linear spring of K0;
//   TwinStiffness  several actuators or slots: T0ᵀ K T0 of the emulated bench's specimen
//                  (T0 = J(0)), else the configured K0 matrix; nullopt for one actuator and one
//                  slot on a one-actuator bench;
//   ReseededTransfer  a transfer spec of a noisy emulated bench with another noise seed.
// Each throws ConfigError naming the slot and what to give when no twin can be made.
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "hybridtest/constitutive/restoring_force_law.h"
#include "hybridtest/substructures/substructure.h"
#include "hybridtest/substructures/substructure_spec.h"

namespace hybridtest::substructures {

// nullptr for a numerical substructure.
std::shared_ptr<const constitutive::RestoringForceLaw> TwinLaw(const Substructure& s,
                                                               const std::string& slot);
std::optional<Eigen::MatrixXd> TwinStiffness(const Substructure& s, const std::string& name);
// nullopt unless `spec` makes an emulated bench of one actuator with noise.
std::optional<TransferSpec> ReseededTransfer(const TransferSpec& spec, unsigned long seed);

}  // namespace hybridtest::substructures
