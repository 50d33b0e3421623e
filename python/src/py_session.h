#pragma once
// hybridtest.Session: a run compiled from a config file or a dict (the same keys), with Python
// transfer systems and laws in place of configured slots, stepped from Python, observed by
// Python callbacks, recorded in memory (and in files when `out` is given, with the same guards
// as the command line: one master per run, results never replaced without overwrite).
//
// The C++ loop runs without the GIL (initialize, step, run); Python code (transfer systems,
// laws, observers) takes it when called. run() is the Session's one loop (Session::Run: paced on
// the config's real_time.clock, or clock=, for a config with `real_time:`; step() is refused
// there) and checks for Ctrl-C between two steps: the run
// holds after the step in progress, every committed step is kept, and KeyboardInterrupt is
// raised (also when it arrives inside a bench driver's call: py_objects.h). step(), run(),
// initialize() and close() called from inside the run's own callbacks are refused
// (hybridtest.Error): the run stops after the step in progress, every committed row kept.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "hybridtest/io/journal.h"
#include "hybridtest/io/run_lock.h"
#include "hybridtest/runner/open_run.h"
#include "hybridtest/runner/session.h"
#include "py_objects.h"

namespace hybridtest::python {

// Keeps every journal row in memory (rows × channels, row-major), as the journal would.
class Recorder final : public runner::SessionObserver {
 public:
  void OnCommit(const runner::CommitEvent& e) override {
    values_.insert(values_.end(), e.row.begin(), e.row.end());
    ++rows_;
  }
  const std::vector<double>& values() const { return values_; }
  long rows() const { return rows_; }

 private:
  std::vector<double> values_;
  long rows_ = 0;
};

// A Python observer: a callable (called per commit) or an object with any of
// on_commit(commit), on_trial(trial), on_stop(status, reason). The arrays it receives are
// read-only views into the run's buffers, valid during the call only (copy to keep them).
class PyObserver final : public runner::SessionObserver {
 public:
  // `actuators`: the names of the trial exchanges, in the run's actuator order (the journal's
  // channel groups).
  PyObserver(py::object observer, const std::vector<std::string>& actuators);  // GIL held
  void OnCommit(const runner::CommitEvent& e) override;
  void OnTrial(const runner::TrialEvent& e) override;
  void OnStop(const runner::StopEvent& e) override;

 private:
  SharedPy on_commit_, on_trial_, on_stop_;
  py::tuple actuators_;       // the exchanges' names
  py::object exchange_type_;  // numpy dtype of one exchange (command, position, force, lab_time)
};

// A resume of a run written to files (hybridtest.resume; `hybridtest resume` on the command
// line): the run's own config (its sidecar's copy) continued from its run state.
struct ResumeArguments {
  std::string csv;                         // the journal of the run to continue
  bool after_safety_stop = false;          // the operator found and fixed the cause
  std::optional<double> force_tolerance;     // [N]
  std::optional<double> position_tolerance;  // [m]
  std::vector<std::string> set;            // KEY=VALUE changes (runner/resume_changes.h)
};

struct SessionArguments {
  py::object config;  // a path (str or os.PathLike) or a dict; None with `resume`
  py::dict transfers;
  py::dict laws;
  std::optional<std::string> out;
  bool overwrite = false;
  std::string command = "run";  // "run" or "simulate" (numerical only)
  std::optional<ResumeArguments> resume;
  // A real-time run's clock ("virtual" or "wall"), over the config's real_time.clock.
  std::optional<std::string> clock;
};

// Python transfer systems and laws in place of the spec's slots. Throws ConfigError.
// A driver's exception is kept in `cause` (see DriverCause).
void Substitute(io::RunSpec& spec, const py::dict& transfers, const py::dict& laws,
                const DriverCauseSlot& cause);

class PySession {
 public:
  explicit PySession(const SessionArguments& args);
  ~PySession();
  void AddObserver(py::object observer);
  std::string Initialize();
  std::string Step();
  std::string Run();
  void RequestStop() { session().RequestStop(); }
  void RaiseError() const;
  void Close();

  runner::Session& session() const;
  const Recorder& recorder() const { return recorder_; }
  const std::vector<io::Channel>& channels() const { return channels_; }
  bool done() const;
  // What a resume repaired on the way (runner::ResumePlan::notes).
  const std::vector<std::string>& notes() const { return notes_; }

 private:
  void StartResume(const SessionArguments& args);  // py_resume.cc
  std::string Advance(bool initialize);
  // `call` on the session without the GIL, then what a callback kept for the caller raised.
  runner::StepResult AdvanceWith(
      const std::function<runner::StepResult(runner::Session&)>& call);
  // Throws hybridtest::Error (and stops the run) if called from inside the run's own step.
  void RefuseReentry(const char* call);
  bool advancing_ = false;              // the C++ step is on the stack (GIL released)
  std::optional<std::string> reentry_;  // a refused re-entry, raised when the step returns
  std::unique_ptr<runner::Session> session_;  // holds the run's lock (a file-backed run)
  Recorder recorder_;
  std::vector<std::unique_ptr<PyObserver>> observers_;
  std::vector<io::Channel> channels_;
  std::vector<std::string> notes_;
  DriverCauseSlot cause_ = std::make_shared<DriverCause>();  // what a bench driver raised
  bool initialized_ = false;
};

}  // namespace hybridtest::python
