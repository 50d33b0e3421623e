#pragma once
// The large-displacement `setup:` of a substructure of several slots and its `safety.slots:`
// (substructure_config.h reads the rest). SI throughout.
//
//   setup:
//     geometry: large_displacement   # rods from a fixed base to the specimen (rod_setup.h);
//                                    # `linear` (the default) is a = p0 + T d with `transform:`
//     p0: [0.02, 0.03]               # [m] actuator positions at zero specimen force
//     directions: [[1, 0], [0, 1]]   # [m/m] e_i, one per slot of `slots:`, in its order: slot i
//                                    # moves the specimen by d_i e_i (2 or 3 coordinates); at
//                                    # most one entry {rotation_about: [x, y(, z)] [m],
//                                    # axis: [ax, ay, az] (3-D only)} turns it by d_i [rad]
//     actuators:                     # one per actuator, in the bench's order
//       - {base: [-0.4, 0.0], attach: [0.0, 0.0]}      # [m] pin on the floor / on the specimen
//       - {base: [-0.24, -0.32], attach: [0.0, 0.0]}   #     (attach: at d = 0)
//     load_cell_zero: [0, 0]         # [N] optional
//
//   safety:
//     ...                            # per actuator, as for a linear setup
//     slots:                         # optional, per slot (a scalar: every slot)
//       max_displacement: [0.04, 0.03]   # [m] |d_i| beyond it: refused before any actuator moves
//       max_force: [400, 300]            # [N] |r_i| beyond it: every actuator holds, the test stops
#include <Eigen/Core>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "hybridtest/common/yaml_input.h"
#include "hybridtest/substructures/linear_setup.h"
#include "hybridtest/substructures/rod_setup.h"
#include "hybridtest/substructures/slot_limits.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::io {

// Actuator k's view of a `safety:` mapping of n actuators: a list gives one value per
// actuator (its length must be n), a scalar applies to every actuator.
YAML::Node PickActuator(const YamlInput& in, const YAML::Node& node, std::size_t k,
                        std::size_t n, const std::string& kp);
// A matrix given as a list of rows; throws ConfigError with `expected` otherwise.
Eigen::MatrixXd ReadMatrix(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                           const char* expected);
// A linear `setup: {p0: [..], transform: [[..]], load_cell_zero: [..]}` for m slots.
substructures::LinearSetup ParseLinearSetup(const YamlInput& in, const YAML::Node& setup,
                                            const std::string& sp, int m);

// True if `setup` declares `geometry: large_displacement`; throws ConfigError for a
// `geometry:` other than linear or large_displacement.
bool IsLargeDisplacementSetup(const YamlInput& in, const YAML::Node& setup, const std::string& sp);

// Reads `setup` (sp: its key path) for m slots. Throws ConfigError naming the key path.
std::shared_ptr<const substructures::RodSetup> ParseRodSetup(const YamlInput& in,
                                                             const YAML::Node& setup,
                                                             const std::string& sp, int m);

// `safety.slots` (kp: the safety section's key path) for the slots `names`; nullopt if absent.
std::optional<substructures::SlotLimits> ParseSlotLimits(const YamlInput& in,
                                                         const YAML::Node& safety,
                                                         const std::string& kp,
                                                         const std::vector<std::string>& names);

// The safety section without its `slots:` (what every actuator's limits are read from).
YAML::Node WithoutSlotLimits(const YAML::Node& safety);

// Refuses (ConfigError at `sp`) a geometry whose J(d) gets nearly singular (σ_min below 1 %
// of that at d = 0) at a slot displacement within every actuator's stroke, in the box of the
// slots' max_displacement or, without it, of the longest stroke from p0 along each direction
// (for a rotational slot: over the shortest lever arm, at most π/2 rad).
void CheckGeometryWithinStroke(const YamlInput& in, const YAML::Node& setup, const std::string& sp,
                               const substructures::RodSetup& geometry,
                               const std::vector<transfer::SafetyLimits>& limits,
                               const std::optional<substructures::SlotLimits>& slot_limits);

}  // namespace hybridtest::io
