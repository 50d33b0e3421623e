#pragma once
// What a resume of RUN.csv continues (`hybridtest resume`, Python's hybridtest.resume()): the run's config (the verbatim text its sidecar
// kept, read as if from its original path so that relative paths resolve as they did), its
// command, its run state, and the first entries of the resume's sidecar record. Refusals
// (docs/safety.md, "Resuming a run") throw ConfigError naming the file and the way out.
#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/io/config.h"
#include "hybridtest/runner/run_state.h"
#include "hybridtest/runner/session.h"

namespace hybridtest::runner {

// What the operator asked for.
struct ResumeRequest {
  std::string csv;                           // the journal of the run to continue
  bool after_safety_stop = false;            // the operator found and fixed the cause
  std::optional<double> force_tolerance;     // [N], recorded in the plan's record
  std::optional<double> position_tolerance;  // [m], recorded in the plan's record
};

struct ResumePlan {
  io::SimulationConfig cfg;
  std::string command;          // "run" or "simulate"
  RunState state;
  long step = 0;                // the committed step resumed from
  double t = 0.0;               // its time [s]
  std::string previous_status;  // the sidecar's status
  nlohmann::json record;        // {"force_tolerance_option_N"?, "position_tolerance_option_m"?,
                                //  "after_safety_stop"?}
  // Per slot: the commands its in-process bench had received when the run stopped (the
  // stop's record), so that a test fault that stopped it does not fire again.
  std::vector<std::optional<long>> commands_received_at_stop;
  // What was repaired on the way, for the operator (e.g. a sidecar whose publication was
  // interrupted, completed).
  std::vector<std::string> notes;
  // The --bench HOST:PORT of the run's start or of its latest resume that gave one ("" none),
  // and whether its start gave one that was not recorded (a run written before it was).
  std::string bench_address;
  bool bench_unrecorded = false;
};

// Reads and checks the run (holding its lock is the caller's part). Throws ConfigError
// (a completed run, no run state, a safety stop without after_safety_stop, inputs changed),
// IoError.
ResumePlan PlanResume(const ResumeRequest& request);

// What a resume runs, for every caller (the command line, Python): the run's own config
// compiled (physical slots refused if the run was a `simulate`) against `bench_address`, else
// the bench the run recorded (a run that gave --bench unrecorded is refused: ConfigError
// naming --bench), the journal as its output, the
// request's tolerances and the `set` changes (KEY=VALUE, resume_changes.h) applied, and the
// session options that record them with `command_line`. `edit`, if given, changes the spec
// before the changes apply (a caller's own transfer systems in place of the configured ones).
struct ResumeSetup {
  io::RunSpec spec;
  SessionOptions options;
};
ResumeSetup PrepareResume(const ResumePlan& plan, const ResumeRequest& request,
                          const std::vector<std::string>& set, const std::string& command_line,
                          std::optional<std::string> bench_address = std::nullopt,
                          const std::function<void(io::RunSpec&)>& edit = {});

}  // namespace hybridtest::runner
