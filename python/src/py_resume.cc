// PySession for a resume (py_session.h): what `hybridtest resume` does (apps: run_commands.cc),
// with Python transfer systems and laws in place of the configured slots.
#include <fmt/core.h>

#include <filesystem>

#include "hybridtest/common/error.h"
#include "hybridtest/runner/open_run.h"
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
  io::RunLock lock = io::RunLock::Acquire(r.csv, "resume");
  const runner::ResumeRequest request{r.csv, r.after_safety_stop, r.force_tolerance,
                                      r.position_tolerance};
  const runner::ResumePlan plan = runner::PlanResume(request);
  notes_ = plan.notes;
  runner::ResumeSetup setup = runner::PrepareResume(
      plan, request, r.set, "python: hybridtest.resume(...)", std::nullopt,
      [&](io::RunSpec& spec) {
        if (args.clock) spec.real_time.clock = *args.clock;  // a real-time run's clock
        Substitute(spec, args.transfers, args.laws, cause_);
      });
  // The front door, as `hybridtest resume`'s: output guards, disk budget, the files the
  // compile read against the run's record.
  opened_.emplace(runner::OpenRun(setup.spec, {.command_line = "python: hybridtest.resume(...)",
                                               .resume = true, .lock = std::move(lock)}));
  channels_ = runner::JournalChannels(setup.spec);
  session_ = std::make_unique<runner::Session>(std::move(setup.spec), std::move(setup.options));
  session_->SetState(plan.state);
  session_->AddObserver(recorder_);
}

}  // namespace hybridtest::python
