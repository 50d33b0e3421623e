#pragma once
// Reads the coupled specimen of a bench with n actuators (`bench.specimen`), in actuator
// coordinates and SI:
//
//   specimen: {type: linear, stiffness: [[k11, k12], [k21, k22]]}        # [N/m], n × n
//   specimen:
//     type: bouc_wen_biaxial          # Park, Wen & Ang (1986); bouc_wen_biaxial.h
//     initial_stiffness: [5000, 3000] # k_i [N/m]: one per actuator, or one for all
//     yield_displacement: 0.004       # Y_i [m]: one per actuator, or one for all
//     alpha: 0.1                      # post-yield stiffness ratio [-]
//     A: 1                            # optional shape parameters [-] (defaults 1, 0.5, 0.5:
//     beta: 0.5                       #   the yield surface |z| = 1 is then the bound)
//     gamma: 0.5
//     max_substep: 0.005              # optional RK4 sub-step in u / Y [-] (default 1/200)
#include <memory>
#include <string_view>

#include <yaml-cpp/yaml.h>

#include "hybridtest/constitutive/vector_law.h"

namespace hybridtest::constitutive {

// `where` is the key path of `node` for errors. Throws ConfigError naming the key, the value
// and the fix (a list of the wrong length names the expected length).
std::unique_ptr<VectorRestoringForceLaw> ParseVectorLaw(const YAML::Node& node, int axes,
                                                        std::string_view where);

}  // namespace hybridtest::constitutive
