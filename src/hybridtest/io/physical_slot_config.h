#pragma once
// The parts of a physical slot's config (substructure_config.h reads the slot and calls these):
// its `transfer:`, `setup:` (one actuator), `safety:` and `initial_stiffness:`. SI throughout;
// every error is a ConfigError naming file:line and the key (common/yaml_input.h).
#include <string>

#include "hybridtest/common/yaml_input.h"
#include "hybridtest/io/substructure_config.h"
#include "hybridtest/substructures/substructure_spec.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::io::internal {

// The transfer system of `node` (`plan --emulate` replaces it by the emulated bench it names).
// `reply_timeout` [s]: the safety section's communication timeout, used by a remote transfer
// unless its own `timeout` is given; `limits`: the slot's safety limits (announced to a bench).
substructures::TransferSpec ParseTransfer(const YamlInput& in, const YAML::Node& node,
                                          const std::string& kp,
                                          const SubstructureOptions& options,
                                          double reply_timeout,
                                          const transfer::SafetyLimits* limits);

// Whether the transfer section `node` talks to a bench over the network (and so takes the
// --bench HOST:PORT address).
bool TakesBenchAddress(const YAML::Node& node);

// `setup:` of a one-actuator slot: p0 [m], sign, scale, force_sign, force_scale,
// load_cell_zero [N]; defaults if absent.
substructures::SetupTransform ParseSetup(const YamlInput& in, const YAML::Node& node,
                                         const std::string& kp);

// `safety:` (required: limits, or `defaults` in so many words).
transfer::SafetyLimits ParseSafety(const YamlInput& in, const YAML::Node& node,
                                   const std::string& kp);

// `initial_stiffness:` K0 [N/m], `measure`, or {measure: true, amplitude: 0.001 m}, into
// `physical`.
void ParseInitialStiffness(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                           substructures::PhysicalSpec& physical);

}  // namespace hybridtest::io::internal
