// See run_commands.h.
#include "run_commands.h"

#include <fmt/core.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>

#include <unistd.h>

#include "command.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/run_lock.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/open_run.h"
#include "hybridtest/runner/paced_loop.h"
#include "hybridtest/runner/progress.h"
#include "hybridtest/runner/resume_plan.h"
#include "hybridtest/runner/session.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/runner/run_record.h"

namespace hybridtest::app {
namespace {

// The session a SIGINT/SIGTERM asks to stop (after the current step: the bench holds, every
// committed step is written). The handler resets itself: a second Ctrl-C ends the process.
std::atomic<runner::Session*> g_signalled_session{nullptr};

class StopOnSignal {
 public:
  explicit StopOnSignal(runner::Session& session) {
    g_signalled_session.store(&session);
    struct sigaction action {};
    action.sa_handler = [](int) {
      if (runner::Session* s = g_signalled_session.load()) s->RequestStop();
    };
    action.sa_flags = SA_RESETHAND;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &old_int_);
    sigaction(SIGTERM, &action, &old_term_);
  }
  ~StopOnSignal() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
    g_signalled_session.store(nullptr);
  }
  StopOnSignal(const StopOnSignal&) = delete;
  StopOnSignal& operator=(const StopOnSignal&) = delete;

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

// The progress display as a session observer: what the events carry, nothing else (behind a
// real-time run's queue it runs on the queue's thread).
class ProgressObserver final : public runner::SessionObserver {
 public:
  explicit ProgressObserver(runner::ProgressOptions options) : progress_(options) {}
  void OnStart(const runner::StartEvent& e) override { duration_ = e.spec.scheme.duration; }
  void OnCommit(const runner::CommitEvent& e) override {
    if (e.kind != runner::RowKind::kCommitted) return;
    const runner::RunStatistics& s = e.statistics;
    progress_.Update({e.step, e.step + e.steps_left, e.t, duration_, s.physical_evaluations,
                      s.lab_time, s.wall_time});
  }
  // The last line tells how the run ended: "done" only when it finished; else the start of
  // the reason (the whole of it follows in the error message).
  void OnStop(const runner::StopEvent& e) override {
    if (e.status == runner::SessionStatus::kFinished) return progress_.Finish("done");
    std::string reason = e.reason;
    if (reason.size() > 100) {
      std::size_t cut = 100;
      while (cut > 0 && (static_cast<unsigned char>(reason[cut]) & 0xC0) == 0x80) --cut;
      reason = reason.substr(0, cut) + "…";
    }
    progress_.Finish(fmt::format(
        "{}: {}", e.status == runner::SessionStatus::kHeld ? "held" : "stopped", reason));
  }

 private:
  runner::Progress progress_;
  double duration_ = 0.0;  // the run's end time [s]
};

// The loop and the summary, shared by run, simulate and resume.
void RunAndReport(io::RunSpec spec, runner::OpenedRun opened,
                  runner::SessionOptions session_options,
                  const runner::RunState* resume_from, bool quiet,
                  const std::string& clock = "",
                  const MonitorCliOptions& monitor = {}) {
  // A file-size limit makes a write fail (EFBIG, reported with the run's status) instead of
  // killing the process mid-row.
  std::signal(SIGXFSZ, SIG_IGN);
  runner::ProgressOptions progress;
  if (quiet || spec.quiet) progress.mode = runner::ProgressMode::kQuiet;
  const std::string command = spec.output.command;
  const std::string csv = spec.output.csv_path;
  // --clock chooses the clock of a real-time run (the session refuses it without `real_time:`).
  if (!clock.empty()) spec.real_time.clock = clock;
  // The delay margins and the process setup of a real-time run, as the session finds them.
  if (progress.mode != runner::ProgressMode::kQuiet) {
    session_options.note = [](const std::string& note) {
      fmt::print(stderr, "hybridtest: {}\n", note);
    };
  }
  // The session refuses an unstable step, and a p0 or limits that disagree with what a bench
  // announces (after any --set), before anything is opened or sent (runner/pre_move_checks.h);
  // a real-time run's pacer is built from its spec (the same Session::Run as every run).
  runner::Session session(std::move(spec), std::move(opened), std::move(session_options));
  if (resume_from != nullptr) session.SetState(*resume_from);
  ProgressObserver progress_observer(progress);
  session.AddObserver(progress_observer);
  const StopOnSignal stop_on_signal(session);
  // --monitor: one more observer, and the operator's Hold/Continue/Stop between two steps.
  std::optional<LiveMonitor> live;
  if (monitor.enabled()) live.emplace(monitor, session);
  // One loop drives every run, paced or not, and the monitor's actions act on each the same
  // way.
  const runner::StepResult result = session.Run();
  if (live) live->Linger(session);
  if (result.status != runner::SessionStatus::kFinished) {
    // How to go on comes first: every committed step is kept, and resume continues from it.
    if (session.statistics().rows > 0 && session.spec().output.files) {
      bool safety = false;
      try {
        std::rethrow_exception(session.error());
      } catch (const transfer::SafetyStop&) {
        safety = true;
      } catch (...) {
      }
      SetErrorHint(fmt::format(
          "every committed step is kept in {}; continue the run with:\n    hybridtest resume "
          "{}{}\n", csv, csv,
          safety ? " --after-safety-stop\n  once the cause is found and fixed (a limit may be "
                   "changed on the way, recorded: --set substructures.SLOT.safety.KEY=VALUE)"
                 : ""));
    }
    std::rethrow_exception(session.error());
  }
  if (quiet) return;
  const runner::PacedLoop* paced = session.paced_loop();
  const runner::RunStatistics& s = session.statistics();
  const io::SchemeSpec& scheme = session.spec().scheme;
  fmt::print("hybridtest {}: {} steps with {}, t = {} s, {} rows -> {}\n", command, s.steps,
             scheme.config.kind == schemes::SchemeKind::kRungeKutta
                 ? fmt::format("{} ({} stages) at {} s", scheme.tableau.name,
                               scheme.tableau.stages(), scheme.dt)
                 : schemes::SchemeKindName(scheme.config.kind) +
                       (scheme.config.adaptive.enabled ? " (adaptive step)"
                                                       : fmt::format(" at {} s", scheme.dt)),
             s.sim_time, s.rows, csv);
  // Durations: seconds with 3 digits below a minute, else 4m01s, 3h08m (runner::FormatDuration).
  auto duration = [](double seconds) {
    return seconds < 59.5 ? fmt::format("{:.3g} s", seconds) : runner::FormatDuration(seconds);
  };
  fmt::print("  wall time {} ({:.3g}x real time)", duration(s.wall_time), s.wall_slowdown);
  if (s.physical_evaluations > 0) {
    // lab time / simulated time: the time a real bench needs against the model's own.
    fmt::print("; {} physical evaluations, lab time {} ({:.3g}x real time)",
               s.physical_evaluations, duration(s.lab_time), s.slowdown);
  }
  fmt::print("\n");
  if (paced != nullptr) {
    // A real-time run: its deadlines, as the sidecar's statistics.real_time records them.
    const runner::PacedStatistics& p = paced->statistics();
    fmt::print("  real time: {} ticks, {} missed deadlines (at most {} in a row{}), {} "
               "overruns; lateness p50 {:.0f} µs, p99 {:.0f} µs, max {:.0f} µs; compute p99 "
               "{:.0f} µs\n", p.ticks, p.misses, p.max_consecutive_misses,
               p.held_on_misses ? ", held" : "", p.overruns, p.late_p50 * 1e6, p.late_p99 * 1e6,
               p.late_max * 1e6, p.compute_p99 * 1e6);
  }
}

}  // namespace

void ExecuteRun(const RunCommandOptions& options) {
  io::RunSpec spec = io::LoadRunSpec(
      options.config,
      {options.bench, options.allow_physical,
       "`simulate` is numerical only: use `hybridtest run` for a hybrid test", std::nullopt});
  if (!options.out.empty()) spec.output.csv_path = options.out;
  spec.output.command = options.command;
  // The front door: lock, output guards, disk budget, input record, provenance.
  runner::OpenedRun opened =
      runner::OpenRun(spec, {.overwrite = options.overwrite, .command_line = command_line()});
  RunAndReport(std::move(spec), std::move(opened), {}, nullptr, options.quiet, options.clock,
               options.monitor);
}

void ExecuteResume(const ResumeCommandOptions& options) {
  // The front door of a resume: the lock before anything of the run is read, the run read and
  // compiled, output guards, disk budget for what is still to come, the files the compile
  // read against the run's record.
  runner::OpenedResume resume = runner::OpenResume(
      {.request = {options.csv, options.after_safety_stop, options.force_tolerance,
                   options.position_tolerance},
       .set = options.set,
       .command_line = command_line(),
       .bench_address = options.bench,
       .planned = [&](const runner::ResumePlan& plan) {
         for (const std::string& note : plan.notes) {
           fmt::print(stderr, "hybridtest resume: {}\n", note);
         }
         if (!options.bench && !plan.bench_address.empty()) {
           fmt::print(stderr, "hybridtest resume: the bench the run recorded, --bench {} (give "
                      "--bench to name another)\n", plan.bench_address);
         }
       }});
  const runner::ResumePlan& plan = resume.plan;
  if (!options.quiet) {
    fmt::print("hybridtest resume: {} from step {} (t = {} s, journal row {}); previous status: "
               "{}\n", options.csv, plan.step, plan.t, plan.state.rows - 1, plan.previous_status);
    std::fflush(stdout);
  }
  RunAndReport(std::move(resume.setup.spec), std::move(resume.opened),
               std::move(resume.setup.options), &plan.state,
               options.quiet, /*clock=*/"", options.monitor);
}

}  // namespace hybridtest::app
