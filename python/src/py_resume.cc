// PySession for a resume (py_session.h): what `hybridtest resume` does (apps: run_commands.cc),
// with Python transfer systems and laws in place of the configured slots.
#include <fmt/core.h>

#include <filesystem>

#include "hybridtest/common/error.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/resume_changes.h"
#include "hybridtest/runner/resume_plan.h"
#include "hybridtest/runner/run_record.h"
#include "py_session.h"

namespace hybridtest::python {

void PySession::StartResume(const SessionArguments& args) {
  const ResumeArguments& r = *args.resume;
  if (!args.config.is_none()) {
    throw ConfigError("Session(resume=...): a resume continues the run's own config (its "
                      "sidecar's copy); give no config");
  }
  if (!std::filesystem::is_regular_file(r.csv)) {
    throw ConfigError(fmt::format("{}: no such journal: give the CSV of the run to resume",
                                  r.csv));
  }
  // One master per run: nothing of the run is read before the lock is held.
  lock_.emplace(io::RunLock::Acquire(r.csv, "resume"));
  const runner::ResumePlan plan =
      runner::PlanResume({r.csv, r.after_safety_stop, r.force_tolerance, r.position_tolerance});
  notes_ = plan.notes;
  io::SubstructureOptions options;
  options.allow_physical = plan.command != "simulate";
  options.physical_hint = "`simulate` is numerical only: use `hybridtest run` for a hybrid test";
  io::RunSpec spec = io::CompileRunSpec(plan.cfg, options);
  RefuseRealTime(spec, "resume()");
  Substitute(spec, args.transfers, args.laws);
  spec.output.csv_path = r.csv;
  spec.output.command = plan.command;
  spec.source.inputs = plan.state.inputs;
  if (r.force_tolerance) spec.resume.force_tolerance = r.force_tolerance;
  if (r.position_tolerance) spec.resume.position_tolerance = r.position_tolerance;
  runner::SessionOptions session_options;
  session_options.resume_record = plan.record;
  if (!r.set.empty()) {
    session_options.resume_record["changes"] = runner::ApplyResumeChanges(spec, r.set);
  }
  session_options.resume_record["command_line"] = "python: hybridtest.resume(...)";
  session_options.commands_received_at_stop = plan.commands_received_at_stop;
  channels_ = runner::JournalChannels(spec);
  session_ = std::make_unique<runner::Session>(std::move(spec), std::move(session_options));
  session_->SetState(plan.state);
  session_->AddObserver(recorder_);
}

}  // namespace hybridtest::python
