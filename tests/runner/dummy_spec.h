#pragma once
// The paper's dummy test as a RunSpec held in memory: the rotor with slot r1 on a numerical
// loopback (a "physical" slot with the default safety limits), Heun at 1 ms, a short run.
#include <string>

#include "hybridtest/io/run_spec_yaml.h"

namespace hybridtest::runner::testing {

inline io::RunSpec DummySpec(double duration) {
  io::RunSpec spec = io::CompileRunSpec(io::ParseSimulationConfig(YamlInput::FromText(
      "model: {name: rotor, blades: 3}\n"
      "initial_state: {q: [0.002, -0.005, 0.002, 0.0], u: [0.1, 0.0, -0.2, 0.5]}\n"
      "integrator: {tableau: heun, dt: 0.001}\n"
      "duration: " + std::to_string(duration) + "\n"
      "substructures:\n"
      "  r1:\n"
      "    type: physical\n"
      "    transfer: {type: loopback, law: {type: linear, stiffness: 7200}}\n"
      "    safety: defaults\n",
      "dummy_spec.yaml")));
  spec.output.files = false;
  spec.quiet = true;
  return spec;
}

}  // namespace hybridtest::runner::testing
