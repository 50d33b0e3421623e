#pragma once
// RunSpec: everything a run needs, as plain data — no YAML inside. A run config (with its
// bench and model files) is compiled into one once (io/run_spec_yaml.h); a C++ or Python
// program may also fill one in directly. The Session (runner/session.h) builds the model's
// substructures and the scheme from it and never writes into it.
//
//   model          the built model (constant) and its resolved parameters
//   x0             the initial state [q; u; z] (2n + extra states), SI
//   scheme         which hybrid scheme, its tableau and steps
//   substructures  one spec per slot of the model, in slot order
//   output         where the run's files go, or none (in memory)
//   source         what the sidecar records about where the spec came from
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "hybridtest/integrators/butcher_tableau.h"
#include "hybridtest/io/real_time_spec.h"
#include "hybridtest/io/run_input.h"
#include "hybridtest/models/catalogue.h"
#include "hybridtest/schemes/scheme_config.h"
#include "hybridtest/substructures/substructure_spec.h"

namespace hybridtest::io {

struct SchemeSpec {
  schemes::SchemeConfig config;         // integrator.scheme and its parameters
  integrators::ButcherTableau tableau;  // runge-kutta only
  double dt = 0.0;                      // step (the first step of an adaptive scheme) [s]
  double duration = 0.0;                // simulated time [s]
  // round(duration / dt), io::StepCount: a fixed-step run takes exactly this many steps, so
  // ValidateRunSpec refuses any other value (a spec filled in code would end early or late).
  long steps = 0;
  // Where dt was given, for messages ("file:line: integrator.dt" from a config file).
  std::string dt_where = "integrator.dt";
};

struct OutputSpec {
  // false: the run writes no file at all (no journal, stage record or run state); observers
  // are its only record. `plan`, campaigns and embedded runs use this.
  bool files = true;
  std::string csv_path;        // the journal; required when files is true
  bool record_stages = true;   // also <run>.stages.csv when a physical slot exists
  bool save_state = true;      // <run>.state.json for `resume`
  std::string command = "run"; // recorded in the sidecar ("run", "simulate", "plan", ...)
};

struct ResumeSpec {
  // Largest |measured − committed| force and position accepted when a resume re-imposes the
  // last committed command. Units: [N], [m]; unset: derived per slot (docs/safety.md).
  std::optional<double> force_tolerance;
  std::optional<double> position_tolerance;
};

struct SourceSpec {
  std::string config_path;   // the run config ("" for a spec written in code)
  std::string config_text;   // its verbatim text
  std::string name;          // the config's stem: default output results/<name>.csv
  int blades = 0;            // rotor only
  // Every file the compile read, in the order read, as the readers report it: the config
  // (when it came from a file), the model file and its `csv:` tables, bench and token files.
  // A program that fills a spec in code names here the files it read, if any. The front door
  // (runner/open_run.h) guards the outputs against these and records them.
  std::vector<RunInput> files;
  // The record of those files, [{role, path (relative to the journal's folder), sha256}]
  // (io/run_inputs.h), made by the front door: kept in the sidecar and every run state;
  // resume checks them.
  nlohmann::json inputs = nlohmann::json::array();
  // The operator's `test:` block (specimen, operator, notes, any keys), as written.
  nlohmann::json test = nlohmann::json::object();
  // Where the record comes from: software (version, git, build type), host, command line,
  // the resolved output path, every input file but a token verbatim with its sha256. Filled
  // by the front door (runner/open_run.h); the sidecar keeps it as it is.
  nlohmann::json provenance = nlohmann::json::object();
  // The --bench HOST:PORT the run's remote transfer systems were pointed at ("" none). The
  // front door records it (provenance "bench"); resume uses it unless given another.
  std::string bench_address;
};

struct RunSpec {
  explicit RunSpec(models::BuiltModel built) : model(std::move(built)) {}

  models::BuiltModel model;
  Eigen::VectorXd x0;  // [q; u; z] (Model::num_states()), SI
  SchemeSpec scheme;
  std::vector<substructures::SubstructureSpec> substructures;  // one per slot
  OutputSpec output;
  ResumeSpec resume;
  // `start: ramp`: a new run ramps from where its actuators are to its first command instead
  // of refusing when they are farther than max_increment (docs/safety.md).
  bool start_ramp = false;
  SourceSpec source;
  RealTimeSpec real_time;  // `real_time:`; disabled: the run is paced by its benches
  bool quiet = false;  // progress: {quiet: true}
};

// The number of steps of size dt [s] in duration [s]: round(duration / dt). Throws
// ConfigError for a non-positive dt or duration, fewer than one or more than kMaxSteps steps,
// or (when `whole`, the case of a fixed step) a duration that is not a whole number of steps
// (within 1e-9 of the duration).
long StepCount(double duration, double dt, bool whole = true);

// Throws ConfigError if the spec cannot make a run: sizes (x0 against the model, one
// substructure per slot, in slot order), a non-positive step or duration, scheme.steps other
// than StepCount(duration, dt) (a fixed-step duration must be a whole number of steps), files
// without a journal path.
void ValidateRunSpec(const RunSpec& spec);

}  // namespace hybridtest::io
