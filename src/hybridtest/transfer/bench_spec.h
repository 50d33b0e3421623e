#pragma once
// EmulatedBenchSpec: the configuration of an emulated bench of n ≥ 1 actuators on ONE specimen
// (EmulatedBench). Each actuator has its own stroke, velocity limit, lag, delay, load cell,
// settling and safety limits (an EmulatedBenchConfig each, bench_config.h); the specimen
// couples them. Its law (constitutive/vector_law.h) is written in actuator coordinates:
// u_k = p_k − p0_k [m] → F_k, the force on actuator k [N].
//
// A bench file has one of two forms, told apart by `actuators:` (read once):
//
//   - one actuator, today's keys (bench_config.h): n = 1, the specimen any scalar law of
//     constitutive/parse_law.h; the bench's own monitor predicts forces from its own secant;
//   - `actuators: n`, a coupled specimen, and a list of n values wherever a key takes one value
//     per actuator (a scalar applies to every actuator):
//
//       bench:
//         actuators: 2
//         specimen: {type: linear, stiffness: [[5000, 1200], [1200, 3000]]}   # [N/m]
//         # or: specimen: {type: bouc_wen_biaxial, initial_stiffness: [5000, 3000],   # [N/m]
//         #                yield_displacement: 0.004, alpha: 0.1}                   # [m], [-]
//         p0_mm: [20, 30]
//         actuator: {lag: {type: none}, delay_ms: [0, 0], velocity_limit_mm_per_s: [20, 40]}
//         load_cell: {noise_std_N: 0}
//         seed: 1                         # actuator k's load cell uses seed + k − 1
//
//     every command vector is checked by the bench's monitors with the specimen's virgin
//     stiffness matrix coupling the predictions (safety_gate.h, CheckCommands); `faults` (a
//     test facility) is not available in this form.
#include <Eigen/Core>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "hybridtest/constitutive/vector_law.h"
#include "hybridtest/transfer/bench_config.h"

namespace hybridtest::transfer {

struct EmulatedBenchSpec {
  // (n ≥ 1) one per actuator. In the `actuators:` form each one's `specimen` is a linear spring
  // of its diagonal stiffness, unused by the bench.
  std::vector<EmulatedBenchConfig> actuators;
  // The coupled specimen law (n axes); null: linear with `stiffness`.
  std::shared_ptr<const constitutive::VectorRestoringForceLaw> specimen;
  // (n × n) the specimen's virgin tangent stiffness in actuator coordinates [N/m] (for a linear
  // specimen, its stiffness).
  Eigen::MatrixXd stiffness;
  // True (the `actuators:` form): the bench's own monitors predict the forces of a command
  // vector coupled through `stiffness`. False (the one-actuator form): each monitor predicts
  // from its own secant, starting from the specimen's initial stiffness.
  bool coupled_safety = true;

  int num_actuators() const { return static_cast<int>(actuators.size()); }
};

// The spec of a bench of one actuator: `config` with its scalar specimen law seen as a law of
// one axis (one-actuator form). Throws ConfigError if `config.specimen` is null.
EmulatedBenchSpec OneActuatorSpec(const EmulatedBenchConfig& config);

// Parses a `bench:` mapping of either form (see above). `where` prefixes errors, e.g.
// "bench.yaml: bench". Throws ConfigError naming the key, the value and the fix.
EmulatedBenchSpec ParseEmulatedBenchSpec(const YAML::Node& bench, std::string_view where);
// Loads a YAML file whose top level holds a `bench:` mapping of either form, reading it once.
// Throws ConfigError (also for an unreadable file or a YAML syntax error, with the line).
EmulatedBenchSpec LoadEmulatedBenchSpec(const std::string& path);

}  // namespace hybridtest::transfer
