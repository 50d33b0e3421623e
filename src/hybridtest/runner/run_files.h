#pragma once
// RunFiles: the records of a file-backed run, one session observer — the journal
// (<run>.csv + sidecar), the stage record (<run>.stages.csv, with a physical slot) and the run
// state (<run>.state.json, for `resume`). They are one observer because their order at a
// commit is the crash-safety contract (decisions 0008 and 0011):
//
//   row 0 of a new run:  appended first (it publishes the journal), then the state saved
//   every later commit:  the state saved (the journal flushed to the kernel first), then the
//                        row appended — with a physical slot, synced before the next trial
//   every trial:         a stage record row (flushed to the kernel every row)
//   resume:              the journal is cut to the state's rows and reopened before anything
//                        moves; a row the crash lost is rewritten from the state; the resume
//                        and its checks go to the sidecar's "resumes"
//   stop:                the sidecar gets the statistics and the status; but a resume that
//                        stops before it commits a step, other than on a safety limit (a
//                        bench it cannot reach, a refused connection, an interrupt), leaves
//                        the status and statistics of the stop it was to continue: its
//                        failure goes to its own entry of "resumes" ("stopped")
//
// The state is saved at every commit of a run with a physical slot, else every 1,000 rows
// and at the end. A real-time run (a `real_time:` block) saves it at its stop only (finished,
// held or stopped), on the stepping thread after every queued row is written: its OnTrial and
// OnCommit use the event's data only, so that they may run on a queue's thread
// (lock_free_observer.h). A real-time run killed outright therefore leaves no state to resume
// from (docs/real-time.md).
#include <optional>

#include "hybridtest/io/journal.h"
#include "hybridtest/io/run_spec.h"
#include "hybridtest/runner/session.h"

namespace hybridtest::runner {

class RunFiles final : public SessionObserver {
 public:
  // `resume_record`: extra fields of the sidecar's resume record.
  RunFiles(const io::RunSpec& spec, nlohmann::json resume_record);

  void OnStart(const StartEvent& event) override;
  void OnTrial(const TrialEvent& event) override;
  void OnCommit(const CommitEvent& event) override;
  void OnResume(const ResumeEvent& event) override;
  void OnStop(const StopEvent& event) override;
  // Appends to the sidecar's "operator_actions" (kept across resumes); nothing before row 0
  // has published the journal.
  void OnOperatorAction(const nlohmann::json& action) override;

 private:
  void SaveState(const CommitEvent& event, bool always, long rows_after);
  void SaveRealTimeState(const StopEvent& event);
  // The stop of a resume that committed nothing (see above); false if it is not that.
  bool KeepPreviousStop(const StopEvent& event);

  const io::RunSpec& spec_;
  nlohmann::json resume_record_;
  bool physical_ = false;       // a physical substructure takes part
  std::optional<io::Journal> journal_;
  std::optional<io::Journal> stages_;
  std::string state_path_;
  long state_rows_ = 0;        // rows of the last saved state
  long rows_cut_ = 0;          // resume: journal rows after the state's, cut before reopening
  bool resume_uncommitted_ = false;  // a resume that has committed no step yet
  bool resume_recorded_ = false;     // ... whose entry of "resumes" is written
  bool row_rewritten_ = false; // resume: the state's row was lost and written again
  Eigen::VectorXd stage_values_;
  // A real-time run: the last committed row written, its step and the rows through it.
  std::vector<double> last_committed_;
  long last_committed_step_ = -1;
  long committed_rows_ = 0;
};

}  // namespace hybridtest::runner
