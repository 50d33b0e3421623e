// PySession for a resume (py_session.h): what `hybridtest resume` does (apps: run_commands.cc),
// with Python transfer systems and laws in place of the configured slots.
#include <fmt/core.h>

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
  // The front door of a resume, as `hybridtest resume`'s: the lock before anything of the run
  // is read, output guards, disk budget, the files the compile read against the run's record.
  runner::OpenedResume resume = runner::OpenResume(
      {.request = {r.csv, r.after_safety_stop, r.force_tolerance, r.position_tolerance},
       .set = r.set,
       .command_line = "python: hybridtest.resume(...)",
       .edit = [&](io::RunSpec& spec) {
         if (args.clock) spec.real_time.clock = *args.clock;  // a real-time run's clock
         Substitute(spec, args.transfers, args.laws, cause_);
       }});
  notes_ = resume.plan.notes;
  channels_ = runner::JournalChannels(resume.setup.spec);
  session_ = std::make_unique<runner::Session>(std::move(resume.setup.spec),
                                               std::move(resume.opened),
                                               std::move(resume.setup.options));
  session_->SetState(resume.plan.state);
  session_->AddObserver(recorder_);
}

}  // namespace hybridtest::python
