#pragma once
// A `type: fmu` substructure in a run config's `substructures:` section (docs/fmi.md):
//
//   substructures:
//     r1:                              # one slot
//       type: fmu
//       fmu: spring.fmu                # the FMU file, relative to this config
//       displacement: x                # the FMU input that receives the slot displacement
//       force: F                       # the FMU output that gives its restoring force
//       parameters: {k: 7200}          # optional: parameter values, in the FMU's own units
//       initial_stiffness: 7200        # optional: K0 [N/m] for the operator-splitting schemes
//     blade:                           # several slots
//       type: fmu
//       slots: [r_flap, r_edge]
//       fmu: blade.fmu
//       displacement: [x_flap, x_edge] # one input and one output per slot, in slot order
//       force: [F_flap, F_edge]
//       initial_stiffness: [[k11, k12], [k21, k22]]
//
// Variables are named, never addressed by value reference. Everything the FMU declares is
// checked here, once, so that a wrong FMU is a ConfigError before anything runs: its FMI
// version and co-simulation support, a binary for this platform, every named variable (its
// causality and type), the units of the displacement and force variables, and state handling.
#include <string>
#include <vector>

#include "hybridtest/common/yaml_input.h"
#include "hybridtest/fmi/fmu_instance.h"
#include "hybridtest/fmi/model_description.h"
#include "hybridtest/substructures/substructure_spec.h"

namespace hybridtest::fmi {

// Whether `node` is a `type: fmu` substructure.
bool IsFmuNode(const YAML::Node& node);

// The spec of the FMU substructure `node` (at key path `kp`) named `name`, serving `slots`
// (the one slot `name` when it is a slot key). Its FMU file is put in *fmu_file (absolute).
// Throws ConfigError naming the FMU file and the variable or capability that is wrong.
substructures::SubstructureSpec ParseFmuSubstructure(const YamlInput& in, const YAML::Node& node,
                                                     const std::string& name,
                                                     const std::vector<std::string>& slots,
                                                     const std::string& kp,
                                                     std::string* fmu_file);

// Shared with the FMU plant's reader (fmu_plant_config.h). Each throws ConfigError naming
// the config place, the FMU file and the variable.
// The FMU file `node.fmu` (relative to the config), checked: co-simulation and a binary for
// this platform; its description into *md. Returns its absolute path.
std::string ReadFmuFile(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                        ModelDescription* md);
// The variable `name` of the FMU, of `causality` and type Real; `role` says what it serves as.
const ModelVariable& Require(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                             const std::string& fmu, const ModelDescription& md,
                             const std::string& name, const char* causality, const char* role);
// The `parameters:` mapping: values of the FMU's parameters, in its units.
std::vector<FmuInstance::Value> ReadParameters(const YamlInput& in, const YAML::Node& node,
                                                const std::string& kp, const std::string& fmu,
                                                const ModelDescription& md);

}  // namespace hybridtest::fmi
