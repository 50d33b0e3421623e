#pragma once
// The run configuration (YAML). One file describes a simulation or a hybrid test:
//
//   model:
//     name: rotor              # rotor | double_pendulum | spinning_top, or instead
//     # file: my_model.yaml    # a model file (docs/model-files.md), relative to this config
//     blades: 3                # rotor only
//     parameters:              # optional overrides, SI units (see `hybridtest models`)
//       k_b: 7200
//       blade1.k_b: 5250       # one blade only
//   initial_state:             # optional; default: the zero state
//     q: [0, 0, 0, 0]          # (n) SI
//     u: [0, 0, 0, 0]          # (n) SI
//   integrator:
//     scheme: runge-kutta      # default; or alpha-os | mr-os (see schemes/scheme_config.h)
//     tableau: heun            # runge-kutta: a catalogue name, or {name, a, b, c, order}
//     dt: 0.001                # step [s] (the first step of an adaptive scheme)
//   duration: 10.0             # simulated time [s]
//   output:
//     csv: results/run.csv     # journal path (overridden by --out)
//   substructures: ...         # hybrid tests: see substructure_config.h
//   progress: {quiet: false}
//   test:                      # optional: what the record says about the test (free keys)
//     specimen: S-0421
//     operator: A. Lab
//     notes: first article
//
// Everything is validated here, where it enters; errors name file:line, key, value and fix.
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "hybridtest/integrators/butcher_tableau.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/io/run_input.h"
#include "hybridtest/models/catalogue.h"
#include "hybridtest/schemes/scheme_config.h"

namespace hybridtest::io {

// The most steps a run may take: 1e9 steps already write ~100 GB of journal.
inline constexpr long kMaxSteps = 1'000'000'000L;

struct SimulationConfig {
  YamlInput input;                    // the parsed file (path, verbatim text, tree)
  models::BuiltModel model;           // built from name, blades and resolved parameters
  int blades = 0;                     // rotor only (0 otherwise)
  Eigen::VectorXd x0;                 // (2n + nz) initial state [q; u; z] (z(0) from the model)
  integrators::ButcherTableau tableau;  // runge-kutta scheme
  schemes::SchemeConfig scheme;         // integrator.scheme and its parameters
  double dt = 0.0;                    // [s]
  double duration = 0.0;              // [s]
  long steps = 0;                     // round(duration / dt)
  std::string output_csv;             // may be empty
  bool quiet = false;
  // resume.force_tolerance: largest |measured − committed force| accepted when `resume`
  // re-imposes the last committed command on a physical slot. Unit: [N]. Unset: 1 % of the
  // slot's force_hard (docs/safety.md, "Resuming a run").
  std::optional<double> resume_force_tolerance;
  // resume.position_tolerance: largest |measured − committed position| accepted when `resume`
  // re-imposes the last committed command. Unit: [m]. Default: a quarter of max_increment.
  std::optional<double> resume_position_tolerance;
  // start: ramp — a new run whose actuators are farther than max_increment from its first
  // command ramps there in steps within max_increment instead of refusing (docs/safety.md,
  // "The start of a run"). Default (`start: check`): refuse.
  bool start_ramp = false;
  // test: the operator's record of the test (specimen, operator, notes, any keys), as written.
  nlohmann::json test = nlohmann::json::object();
  // The files read so far, in the order read: the config itself (when it was loaded from a
  // file), the model file and its `csv:` tables. CompileRunSpec adds the bench and token files.
  std::vector<RunInput> files{};
};

// Loads and validates a config file. Throws ConfigError.
SimulationConfig LoadSimulationConfig(const std::string& path);
// Same from text (tests, a Python dict, the copy a resumed run's sidecar keeps): `files` then
// does not name the config (no file was read for it).
SimulationConfig ParseSimulationConfig(const YamlInput& input);

// The model described by a `model:` section: a built-in name or a model file. If `files` is
// given, the model file and every `csv:` table it reads are appended to it.
models::BuiltModel ParseModel(const YamlInput& input, const YAML::Node& model_node, int* blades,
                              std::vector<RunInput>* files = nullptr);

// The scheme named by `integrator.scheme` and its parameters (not the tableau and dt).
schemes::SchemeConfig ParseScheme(const YamlInput& input, const YAML::Node& integrator_node);

// A tableau given by name or as a mapping; validated.
integrators::ButcherTableau ParseTableau(const YamlInput& input, const YAML::Node& node,
                                         std::string_view key_path);

}  // namespace hybridtest::io
