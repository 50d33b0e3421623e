// See resume_plan.h.
#include "hybridtest/runner/resume_plan.h"

#include <fmt/core.h>

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <tuple>
#include <utility>

#include "hybridtest/common/error.h"
#include "hybridtest/io/journal.h"
#include "hybridtest/io/run_inputs.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/resume_changes.h"

namespace hybridtest::runner {

namespace {

// A journal publishes by renaming its staged CSV, then its staged sidecar (journal.h): a crash
// between the two renames leaves the CSV beside "<sidecar>.partial". Resume (which holds the
// run's lock) completes that rename: both files belong to the same run.
// Returns a note for the operator when it did.
std::string CompleteInterruptedPublish(const std::string& csv) {
  const std::string sidecar = io::SidecarPath(csv);
  const std::string staged = io::StagedPath(sidecar);
  std::error_code ec;
  if (std::filesystem::exists(sidecar, ec) || !std::filesystem::is_regular_file(staged, ec)) {
    return "";
  }
  std::filesystem::rename(staged, sidecar, ec);
  if (ec) {
    throw IoError(fmt::format("{}: the run's sidecar is still staged as {} and cannot be "
                              "renamed: {}", csv, staged, ec.message()));
  }
  return fmt::format("{}: the run was stopped while publishing its sidecar; {} completed from {}",
                     csv, sidecar, staged);
}

// The commands each slot's bench had received when the run stopped, where recorded.
std::vector<std::optional<long>> CommandsReceivedAtStop(const nlohmann::json& sidecar) {
  std::vector<std::optional<long>> out;
  const auto stats = sidecar.find("statistics");
  if (stats == sidecar.end() || !stats->is_object()) return out;
  const auto stop = stats->find("stop");
  if (stop == stats->end() || !stop->is_object()) return out;
  const auto received = stop->find("commands_received");
  if (received == stop->end() || !received->is_array()) return out;
  for (const auto& entry : *received) {
    out.push_back(entry.is_number_integer() ? std::optional<long>(entry.get<long>())
                                            : std::nullopt);
  }
  return out;
}

// The --bench of the run's latest resume that gave one, else of its start ("" none); and
// whether the start's command line gave one its record does not hold.
std::pair<std::string, bool> RecordedBench(const nlohmann::json& sidecar) {
  const nlohmann::json none = nlohmann::json::object();
  const auto resumes = sidecar.value("resumes", nlohmann::json::array());
  for (auto r = resumes.rbegin(); r != resumes.rend(); ++r) {
    if (r->is_object() && r->value("bench", std::string()) != "") return {r->value("bench", ""), false};
  }
  const nlohmann::json extra = sidecar.value("extra", none);
  const nlohmann::json provenance = extra.is_object() ? extra.value("provenance", none) : none;
  if (!provenance.is_object()) return {"", false};
  const std::string bench = provenance.value("bench", std::string());
  const std::string line = provenance.value("command_line", std::string());
  return {bench, bench.empty() && line.find("--bench") != std::string::npos};
}

// Why a run has no run state, from what its journal and sidecar say. A real-time run keeps its
// state in memory and writes it when it stops (a hold, a stop, its end: runner/run_files.cc);
// one killed (kill -9, a power cut) never wrote it, though its journal holds committed rows.
std::string NoStateMessage(const std::string& csv, const std::string& state_path,
                           const nlohmann::json& sidecar, const std::string& status) {
  const long rows = ReadJournalRows(csv, {}).complete;
  bool real_time = false;
  try {
    const YAML::Node config = YAML::Load(sidecar.value("config", std::string()));
    const YAML::Node rt = config["real_time"];
    real_time = rt && !rt.IsNull() && !(rt.IsScalar() && rt.Scalar() == "false");
  } catch (const std::exception&) {
    // An unreadable config copy: the generic reason below.
  }
  const std::string restart = fmt::format(
      "start the test again with another --out (or hybridtest run --overwrite {} to replace "
      "it)", csv);
  if (real_time && rows > 0) {
    return fmt::format(
        "{}: no run state {} beside it. This is a real-time run: it writes its state only when "
        "it stops (Stop, a hold, a safety stop or its end), and it was {} before it could, so "
        "its last committed point was never verified and recorded; resume cannot continue it "
        "without risking a step run twice on the specimen. Its {} journal rows are kept as "
        "they are: {}",
        csv, state_path,
        status == "running" ? "killed (status 'running': kill -9, a crash or a power cut)"
                            : "ended with status '" + status + "'",
        rows, restart);
  }
  if (rows > 0) {
    return fmt::format(
        "{}: no run state {} beside it, though its journal holds {} rows (status '{}'): the "
        "state was removed, or the run was written without one (by a program that turned it off, "
        "or by a hybridtest without resume). Restore the state if you have the one the run wrote "
        "last; otherwise {}",
        csv, state_path, rows, status, restart);
  }
  return fmt::format("{}: no run state {} beside it: the run stopped before its first "
                     "committed row; {}", csv, state_path, restart);
}

// PlanResume without the translation of JSON type errors.
ResumePlan PlanResumeChecked(const ResumeRequest& options) {
  if (!std::filesystem::exists(options.csv)) {
    throw ConfigError(fmt::format("{}: no such journal: give the CSV of the run to resume",
                                  options.csv));
  }
  const std::string note = CompleteInterruptedPublish(options.csv);
  const nlohmann::json sidecar = io::ReadSidecar(options.csv);
  const std::string status = sidecar.value("status", "");
  if (status == "completed") {
    throw ConfigError(fmt::format("{}: the run is completed; there is nothing to resume",
                                  options.csv));
  }
  std::string stop_kind;
  if (sidecar.contains("statistics") && sidecar["statistics"].contains("stop")) {
    const auto& stop = sidecar["statistics"]["stop"];
    stop_kind = stop.value("kind", "");
    // A refused resume (force check) may be retried without the flag: nothing new happened.
    const std::string limit = stop.value("limit", "");
    if (stop_kind == "safety" && limit != "resume_force_tolerance" &&
        limit != "resume_position_tolerance" &&
        !options.after_safety_stop) {
      throw ConfigError(fmt::format(
          "{}: the run stopped on a safety limit ({}: {}). Resume retries the step that was "
          "stopped, with the limits the run started with: find and fix the cause first "
          "(docs/safety.md, \"Resuming a run\"), then run\n    hybridtest resume {} "
          "--after-safety-stop\nand, if a limit must change, add --set "
          "substructures.SLOT.safety.KEY=VALUE (recorded in the sidecar)",
          options.csv, stop.value("limit", "?"), stop.value("message", ""), options.csv));
    }
  }
  const std::string state_path = RunStatePath(options.csv);
  if (!std::filesystem::exists(state_path)) {
    throw ConfigError(NoStateMessage(options.csv, state_path, sidecar, status));
  }
  // The state cannot lie: its checksum (LoadRunState), then its agreement with the journal,
  // before anything is cut or moved.
  RunState state = LoadRunState(state_path);
  VerifyRunStateAgainstJournal(state, options.csv);
  const std::string command = sidecar.value("command", "run");
  if (command != "run" && command != "simulate") {
    throw ConfigError(fmt::format("{}: made by `hybridtest {}`; only run and simulate can be "
                                  "resumed", options.csv, command));
  }
  // The run's own files, found from the run's directory (never the current one); the front
  // door (open_run.h) checks what the compile read against the digests recorded when it
  // started. The config is the sidecar's copy, read as the run's config.
  const std::string config_path = io::RecordedConfigPath(state.inputs, options.csv);
  io::SimulationConfig cfg = io::ParseSimulationConfig(YamlInput::FromText(
      sidecar.value("config", ""), config_path, "keys such as model:, integrator:, duration:"));
  cfg.files.insert(cfg.files.begin(), io::RunInput{"config", config_path});
  ResumePlan plan{.cfg = std::move(cfg), .command = command, .state = std::move(state),
                  .step = 0, .t = 0.0, .previous_status = status, .record = {},
                  .commands_received_at_stop = {}, .notes = {}, .bench_address = {},
                  .bench_unrecorded = false};
  plan.step = plan.state.scheme.value("step", 0L);
  plan.t = plan.state.scheme.value("t", 0.0);
  plan.record = nlohmann::json::object();
  if (options.force_tolerance) plan.record["force_tolerance_option_N"] = *options.force_tolerance;
  if (options.position_tolerance) {
    plan.record["position_tolerance_option_m"] = *options.position_tolerance;
  }
  if (options.after_safety_stop) plan.record["after_safety_stop"] = true;
  plan.commands_received_at_stop = CommandsReceivedAtStop(sidecar);
  std::tie(plan.bench_address, plan.bench_unrecorded) = RecordedBench(sidecar);
  if (!note.empty()) plan.notes.push_back(note);
  return plan;
}

}  // namespace

ResumePlan PlanResume(const ResumeRequest& options) {
  try {
    return PlanResumeChecked(options);
  } catch (const nlohmann::json::exception& e) {
    // A sidecar or state with a value of the wrong JSON type (edited by hand or damaged).
    throw ConfigError(fmt::format("{}: the run's sidecar or state holds a value of the wrong "
                                  "type ({}); restore the files the run wrote", options.csv,
                                  e.what()));
  }
}

ResumeSetup PrepareResume(const ResumePlan& plan, const ResumeRequest& request,
                          const std::vector<std::string>& set, const std::string& command_line,
                          std::optional<std::string> bench_address,
                          const std::function<void(io::RunSpec&)>& edit) {
  if (!bench_address && !plan.bench_address.empty()) bench_address = plan.bench_address;
  if (!bench_address && plan.bench_unrecorded) {
    throw ConfigError(fmt::format(
        "{}: the run was started with --bench HOST:PORT (its sidecar's extra.provenance."
        "command_line), but its record does not say which bench: give the same one again, "
        "`hybridtest resume {} --bench HOST:PORT`; nothing was moved", request.csv,
        request.csv));
  }
  io::SubstructureOptions options;
  options.bench_address = bench_address;
  options.allow_physical = plan.command != "simulate";
  options.physical_hint = "`simulate` is numerical only: use `hybridtest run` for a hybrid test";
  ResumeSetup setup{io::CompileRunSpec(plan.cfg, options), {}};
  io::RunSpec& spec = setup.spec;
  if (edit) edit(spec);
  spec.output.csv_path = request.csv;
  spec.output.command = plan.command;
  spec.source.inputs = plan.state.inputs;
  if (request.force_tolerance) spec.resume.force_tolerance = request.force_tolerance;
  if (request.position_tolerance) spec.resume.position_tolerance = request.position_tolerance;
  setup.options.resume_record = plan.record;
  if (!set.empty()) setup.options.resume_record["changes"] = ApplyResumeChanges(spec, set);
  setup.options.resume_record["command_line"] = command_line;
  if (bench_address) setup.options.resume_record["bench"] = *bench_address;
  setup.options.commands_received_at_stop = plan.commands_received_at_stop;
  return setup;
}

}  // namespace hybridtest::runner
