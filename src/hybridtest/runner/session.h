#pragma once
// Session: one run of a hybrid test (or a simulation), held in the caller's hands. Built from a
// RunSpec (io/run_spec.h); it builds the substructures and the scheme and drives the scheme one
// committed step at a time (decision 0014):
//
//   Initialize()   observers start (a file-backed run's records open first: a run that cannot
//                  write must not move anything); substructures activate; K0 ramps where
//                  asked; r_0 = trial at x_0 (step 0, stage 0), committed     ◄ steel moves
//                  — or, after SetState(), the run continues from that state: the bench is
//                  brought back to the last committed command and checked (docs/safety.md)
//   Step()         scheme.Step(seam): its trials go through the seam, which tries every
//                  substructure at the slot displacements d the scheme computed and reports
//                  each trial to the observers (OnTrial); then the substructures commit and
//                  the observers receive the committed row (OnCommit)
//
// Step() and Initialize() never throw for what happens in a run: a failure (SafetyStop,
// TransferError, a singular mass matrix, a write error) puts every substructure on Hold(),
// tells the observers (OnStop) and returns kStopped with the reason; error() holds the
// exception. RequestStop() (any thread, or a signal handler) ends the run after the step in
// progress: every substructure holds and Step() returns kHeld. A finished run deactivates its
// substructures and returns kFinished. Then every further Step() returns the same result.
//
// Observers are called on the stepping thread, in the order they were added, and must not
// throw (an observer's exception stops the run like any failure). The row an OnCommit carries
// is the journal row: t, x ([q; u; z]), r (m), then per physical slot command, position, force and
// lab time (SI, runner/run_record.h); intermediate rows (MR-OS's substeps) carry NaN there.
#include <atomic>
#include <chrono>
#include <optional>
#include <exception>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/common/clock.h"
#include "hybridtest/io/run_spec.h"
#include "hybridtest/runner/opened_run.h"
#include "hybridtest/runner/run_state.h"
#include "hybridtest/runner/slot_map.h"
#include "hybridtest/schemes/hybrid_scheme.h"
#include "hybridtest/substructures/substructure.h"

namespace hybridtest::runner {

enum class SessionStatus {
  kWorking,   // a step was committed; more to go
  kFinished,  // the run reached its end; substructures deactivated
  kHeld,      // stopped on request (RequestStop); substructures hold; resumable
  kStopped,   // stopped by a failure (reason, error()); substructures hold; resumable
};
const char* StatusName(SessionStatus status);

struct StepResult {
  SessionStatus status = SessionStatus::kWorking;
  std::string reason;  // why a run is held or stopped ("" otherwise)
};

struct RunStatistics {
  long steps = 0;                 // committed steps
  long rows = 0;                  // committed rows (the journal's rows)
  long physical_evaluations = 0;  // trials sent to benches
  double sim_time = 0.0;          // simulated time reached [s]
  double wall_time = 0.0;         // [s]
  double lab_time = 0.0;          // lab time reported by the benches [s]
  double slowdown = 0.0;          // lab time / simulated time (0 without a bench) [-]
  double wall_slowdown = 0.0;     // wall time / simulated time [-]
};
nlohmann::json ToJson(const RunStatistics& s);

// One trial of every substructure (a physical one moved): where, d (m) [m], r (m) [N], and the
// exchange of each physical slot (in slot order; command, position, force, lab time, SI).
// Resume moves are trials too: stage −2 a ramp move, −1 the re-imposition.
struct TrialEvent {
  schemes::TrialPoint at;
  std::span<const double> d;
  std::span<const double> r;
  std::span<const substructures::Exchange> exchanges;
};

enum class RowKind {
  kCommitted,     // a committed point with its specimen sample (rows 0, 1, ... of a step)
  kIntermediate,  // a committed point between samples (MR-OS substeps): NaN physical channels
  kUncommitted,   // after a failure: the state a step computed but could not try; NaN r
};

// A real-time run's pacer as it stands at a committed row (published by the pacer,
// runner/paced_loop.h, on the stepping thread; valid during the OnCommit that carries it).
struct RealTimeSample {
  long ticks = 0;
  long misses = 0;
  long misses_in_a_row = 0;      // now
  long max_misses_in_a_row = 0;  // so far
  long overruns = 0;
  double late = 0.0;     // this tick's wake-up − its deadline [s]
  double compute = 0.0;  // the tick before's Session::Step() [s] (this tick's is still going)
  // J2 and J3 of the first actuator, then J1 (a live estimate) [ms], J2 and J3 [%] of every
  // actuator in the run's order (runner/tracking_criteria.h; NaN before they are known).
  double J2 = 0.0, J3 = 0.0;
  std::span<const double> J1_ms, actuator_J2, actuator_J3;
  // The delay the compensator in front of each actuator removes, its current estimate, in the
  // run's order (TransferSystem::actuator_compensated_delay; 0 without a compensator). [s]
  std::span<const double> compensated_delay_s;
};

// What a run is, given to every observer before anything is activated (OnStart). The
// references are valid during OnStart only: an observer copies what it keeps and holds no
// pointer to the Session (every later event carries what it needs).
struct StartEvent {
  const io::RunSpec& spec;
  const SlotMap& slot_map;  // which substructure serves which slot through which actuators
  // The run's substructures (their actuators' p0 and limits, their transfer systems), which
  // outlive every event of the run.
  const std::vector<std::unique_ptr<substructures::Substructure>>& substructures;
  bool has_physical = false;  // a physical substructure takes part
  const RunState* resume = nullptr;  // the state a resume continues from; null: a new run
  std::string clock;  // a real-time run's clock ("wall", "virtual", ...); "" without real time
};

struct CommitEvent {
  RowKind kind = RowKind::kCommitted;
  long step = 0;                 // committed steps
  double t = 0.0;                // [s]
  std::span<const double> x;     // [q; u; z]
  std::span<const double> r;     // (m)
  std::span<const double> row;   // the journal row (see above)
  RunStatistics statistics;      // the run's statistics at this row
  bool finished = false;         // the scheme reached the run's end with this row
  long steps_left = 0;           // steps still to go (an estimate for adaptive schemes)
  // The committed state at this row, for a run-state file (runner/run_state.h; its rows and
  // journal fields are the caller's to fill). Callable during OnCommit on the stepping thread
  // only; empty on an event a queue delivers (lock_free_observer.h) and on other rows.
  std::function<RunState()> state;
  // A real-time run's pacer at this row (committed rows; null otherwise and on an event a
  // queue delivers).
  const RealTimeSample* real_time = nullptr;
};

struct StopEvent {
  SessionStatus status = SessionStatus::kFinished;  // kFinished, kHeld or kStopped
  std::string reason;            // "" when finished
  nlohmann::json statistics;     // ToJson(statistics) + initial_stiffness (+ stop details)
  // The last committed point (step −1 before the first) and the state at it, for a run that
  // saves its state at the stop (a real-time run: run_files.h); no state before the scheme
  // exists.
  long committed_step = -1;
  std::optional<RunState> state;
};

// A resume, in two phases: kRestored once every substructure and the scheme hold the saved
// state (before anything moves; `row` is the state's committed row), then kChecked after the
// bench was brought back and checked (`checks`, one per physical slot) or kRefused if a check
// or a move failed (`refused` says why; a kStopped result follows).
struct ResumeEvent {
  enum Phase { kRestored, kChecked, kRefused } phase = kRestored;
  const RunState* state = nullptr;
  std::span<const double> row;
  long step = 0;    // the committed point the run continues from (kChecked, kRefused)
  double t = 0.0;   // ... its time [s]
  nlohmann::json checks = nlohmann::json::array();
  std::string refused;
};

class Session;
class RunFiles;
class ConstraintForceRecorder;
class PacedLoop;
class LockFreeObserver;

class SessionObserver {
 public:
  virtual ~SessionObserver() = default;
  // Before anything is activated; a file-backed run's records open here.
  virtual void OnStart(const StartEvent& /*event*/) {}
  // Before every trial (a physical substructure moves next).
  virtual void BeforeTrial(const schemes::TrialPoint& /*at*/) {}
  virtual void OnTrial(const TrialEvent& /*event*/) {}
  virtual void OnCommit(const CommitEvent& /*event*/) {}
  virtual void OnResume(const ResumeEvent& /*event*/) {}
  // An operator's hold, continue or stop (its time and origin), between two steps: a
  // file-backed run appends it to the sidecar's "operator_actions" (Session::
  // RecordOperatorAction).
  virtual void OnOperatorAction(const nlohmann::json& /*action*/) {}
  virtual void OnStop(const StopEvent& /*event*/) {}
  // Before OnStop (every observer first): add this observer's own fields to the statistics
  // the sidecar records (e.g. a paced loop's `real_time`).
  virtual void AddStatistics(nlohmann::json& /*statistics*/) {}
  // True for an observer that neither blocks, allocates nor writes a file in OnTrial and
  // OnCommit (a paced loop, the monitor's ring): a paced run keeps it on the stepping thread
  // and puts every other observer behind one lock-free queue (runner/real_time_setup.h).
  virtual bool real_time_safe() const { return false; }
};

struct SessionOptions {
  // Resume: commands each slot's in-process bench had received when the run stopped (from the
  // stopped run's record), so that a test fault that stopped it does not fire again.
  std::vector<std::optional<long>> commands_received_at_stop;
  // Extra fields of the sidecar's resume record (e.g. the tolerances the operator gave).
  nlohmann::json resume_record = nlohmann::json::object();
  // The checks made before anything moves (runner/pre_move_checks.h: the scheme's stability
  // at the initial state, each bench's p0 and limits against the setup), made by the
  // constructor. false skips them: only for a caller that has made them itself, or a study
  // that wants an unstable step to diverge. The command line has no way to skip them.
  bool pre_move_checks = true;
  // Messages for the operator before anything moves and as the run starts (a real-time run's
  // delay margin per slot, what the process setup of a wall-clock run did); null: none. The
  // command line prints them; they are in the sidecar's statistics.real_time too.
  std::function<void(const std::string&)> note;
  // The clock of a real-time run instead of the one the spec names (a test's simulated wall
  // clock); not owned, outlives the session. Null: the spec's.
  Clock* clock = nullptr;
};

// How the one loop of Session::Run() paces its steps: a real-time run's PacedLoop (decision
// 0016), which the Session builds from its spec; without one the steps follow each other at
// once (lab time). Called on the stepping thread.
class StepPacer {
 public:
  virtual ~StepPacer() = default;
  // After a successful Initialize(), before the first Step(): starts every transfer system
  // paced. Throws to refuse (the session then holds every actuator and rethrows).
  virtual void Start() = 0;
  // Before each Step(): waits for the step's tick. `after_hold`: an operator's hold came
  // between this step and the last (the next tick is one step after now).
  virtual void BeforeStep(bool after_hold) = 0;
  // After each Step().
  virtual void AfterStep(const StepResult& result) = 0;
  // What it publishes at a committed row, for the live monitor (null: nothing). On the
  // stepping thread, without allocating.
  virtual const RealTimeSample* Sample() { return nullptr; }
};

class Session {
 public:
  // Validates the spec (io::ValidateRunSpec), builds the substructures and makes the checks
  // before moving (SessionOptions::pre_move_checks); nothing is activated, opened or moved.
  // With `real_time:` (spec.real_time.enabled) it builds its pacer: the clock the spec names
  // (wall or virtual), a PacedLoop (runner/paced_loop.h: refuses a scheme or a transfer system
  // that cannot run paced) and the delay stability check of every physical slot
  // (runner/delay_stability.h: refuses an unstable slot unless real_time.force). A clock
  // without `real_time:` is refused. Throws ConfigError.
  //
  // A run that writes files (spec.output.files) is made from the run the front door opened for
  // it (runner/open_run.h: OpenRun, OpenResume), and from nothing else: `opened` must be the
  // OpenedRun of spec's journal (ConfigError otherwise, before anything is built); the session
  // holds its lock until it is destroyed. A run in memory needs none (the first form refuses a
  // file-backed spec, naming the front door).
  explicit Session(io::RunSpec spec, SessionOptions options = {});
  Session(io::RunSpec spec, OpenedRun opened, SessionOptions options = {});
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // Observers are not owned and must outlive the session; add them before Initialize().
  void AddObserver(SessionObserver& observer);
  // Replaces the observers with `observers` and returns the ones it had, in their order (the
  // run's files first): a paced run puts them behind a queue. Before Initialize().
  std::vector<SessionObserver*> ExchangeObservers(std::vector<SessionObserver*> observers);

  // Continue from a saved state (before Initialize()). Throws ConfigError if it does not fit
  // the spec (slots, sizes).
  void SetState(const RunState& state);
  // The committed state now (everything resume needs; rows/journal fields are the file
  // observer's to fill).
  RunState GetState() const;

  // A real-time run first puts every observer that is not real_time_safe() behind one
  // lock-free queue (runner/real_time_setup.h: the stepping thread writes no file).
  StepResult Initialize();
  // One step, unpaced (a real-time run is stepped by Run()).
  StepResult Step();
  // The one loop of every run, from every front (the command line, Python, campaigns):
  // Initialize() (unless done), then, while working, the between-steps hook (the operator's
  // Hold/Continue/Stop, Python's signal check), the pacer's wait for the tick (a real-time
  // run) and Step(). A real-time run on the wall clock first prepares the process
  // (PrepareRealTimeProcess, reported through SessionOptions::note). Throws ConfigError when a
  // transfer system refuses to start paced (every actuator holds).
  StepResult Run();
  // Real time is a setting of the session (decision 0016), read from its spec: the paced loop
  // (null without `real_time:`).
  const PacedLoop* paced_loop() const { return paced_loop_.get(); }
  // Called by Run() on the stepping thread before every step (after Initialize()): may hold
  // (HoldBetweenSteps, then ContinueAfterHold) or end the run (InterruptBetweenSteps); returns
  // the session's result. The live monitor's operator control and Python's signal check set
  // it.
  void SetBetweenSteps(std::function<StepResult(Session&)> hook) { between_steps_ = std::move(hook); }
  // Holds so far (HoldBetweenSteps), for a pacer to restart its ticks after one.
  long holds() const { return holds_; }
  // Thread- and async-signal-safe.
  void RequestStop() noexcept { stop_requested_.store(true, std::memory_order_relaxed); }
  // The same from the stepping thread, with the reason the stop reports instead of the
  // operator (e.g. a paced loop's missed deadlines). Not signal-safe.
  void RequestStop(std::string reason) {
    stop_reason_ = std::move(reason);
    RequestStop();
  }
  bool stop_requested() const noexcept { return stop_requested_.load(std::memory_order_relaxed); }
  // An operator's hold between two steps (on the stepping thread, while working): every
  // substructure holds its position (Hold()); nothing moves until ContinueAfterHold(), which
  // activates them again and returns the status (kStopped, with error(), if a bench refuses).
  void HoldBetweenSteps() noexcept;
  StepResult ContinueAfterHold();
  // Ends a working run between two steps, without another step, as RequestStop() does after
  // one: every substructure holds, the observers hear the stop, the result is kHeld with an
  // Interrupted error.
  StepResult InterruptBetweenSteps();
  // Appends `action` (an operator's hold, continue or stop, with its time and origin) to the
  // sidecar's "operator_actions" of a file-backed run (every observer's OnOperatorAction, on
  // the stepping thread; behind a real-time run's queue once the queue is drained).
  void RecordOperatorAction(const nlohmann::json& action);

  const io::RunSpec& spec() const { return spec_; }
  const multibody::Model& model() const { return spec_.model.model; }
  const RunStatistics& statistics() const { return stats_; }
  const StepResult& result() const { return result_; }
  // The last committed point (valid after a successful Initialize()).
  const schemes::CommittedPoint& committed() const;
  const schemes::HybridScheme* scheme() const { return scheme_.get(); }
  const std::vector<std::unique_ptr<substructures::Substructure>>& substructures() const {
    return subs_;
  }
  // Which substructure serves which slot through which actuators (slot_map.h).
  const SlotMap& slot_map() const { return slot_map_; }
  bool has_physical() const { return physical_count_ > 0; }
  // The state SetState() gave (nullptr for a new run).
  const RunState* resume_state() const { return resume_ ? &*resume_ : nullptr; }
  // Steps still to go (estimate for adaptive schemes).
  long EstimatedStepsLeft() const;
  // The failure that stopped the run, if any.
  std::exception_ptr error() const { return error_; }

 private:
  class Seam;
  class Rows;
  void MeasureRequestedStiffness();
  // The start check of every substructure (Substructure::CheckStart) at the initial slot
  // displacements d0 (m) [m]; fills start_record_. Throws SafetyStop, TransferError.
  void CheckStart(const Eigen::VectorXd& d0);
  void BuildScheme();
  // The pacer of a real-time run (spec_.real_time), with its delay stability check.
  void BuildPacer();
  void Note(const std::string& message) const;
  void RestoreFromState();
  void ReimposeCommitted();
  void FillRow(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& r, bool measured);
  void Publish(RowKind kind, long step, double t, const Eigen::VectorXd& x,
               const Eigen::VectorXd& r);
  void PublishTrial(const schemes::TrialPoint& at, const Eigen::Ref<const Eigen::VectorXd>& d,
                    const Eigen::Ref<const Eigen::VectorXd>& r);
  void UpdateStatistics(double t);
  StepResult Fail(const std::exception& e);
  StepResult Finish();
  // The last committed step and the state at it (StopEvent), once a scheme exists.
  void AddCommittedState(StopEvent& event) const;
  double WallTime() const;

  OpenedRun opened_;  // the run's lock (file-backed), released last
  io::RunSpec spec_;
  SessionOptions options_;
  std::vector<std::unique_ptr<substructures::Substructure>> subs_;
  std::unique_ptr<RunFiles> files_;  // the journal, stage record and run state (file-backed)
  std::vector<SessionObserver*> observers_;
  std::unique_ptr<schemes::HybridScheme> scheme_;
  std::unique_ptr<Seam> seam_;
  std::unique_ptr<Rows> rows_sink_;
  std::optional<RunState> resume_;
  std::atomic<bool> stop_requested_{false};
  std::string stop_reason_;  // RequestStop(reason); "" for the operator
  StepResult result_;
  bool initialized_ = false;
  int physical_count_ = 0;
  RunStatistics stats_;
  nlohmann::json stiffness_record_ = nlohmann::json::array();
  nlohmann::json start_record_ = nlohmann::json::array();
  std::exception_ptr error_;
  double t_now_ = 0.0;
  double wall_offset_ = 0.0;  // wall time of the sessions before a resume [s]
  std::chrono::steady_clock::time_point wall_start_;
  // Preallocated per-step buffers.
  Eigen::VectorXd row_;
  std::unique_ptr<ConstraintForceRecorder> forces_;  // the row's constraint forces, if any
  Eigen::VectorXd r0_;
  std::vector<substructures::Exchange> exchanges_;  // per actuator of the physical substructures
  // The model slots each substructure serves (its d and r, in its order), and their buffers.
  std::vector<std::vector<int>> slot_of_;
  SlotMap slot_map_;
  // Real time (spec.real_time): the clock, the pacer and the queue in front of the observers
  // that may not run on the stepping thread.
  std::unique_ptr<Clock> own_clock_;
  Clock* clock_ = nullptr;  // own_clock_ or SessionOptions::clock
  std::unique_ptr<PacedLoop> paced_loop_;
  std::unique_ptr<LockFreeObserver> queue_;
  StepPacer* pacer_ = nullptr;
  std::function<StepResult(Session&)> between_steps_;
  long holds_ = 0;
  bool paced_ = false;  // the pacer has started
  std::vector<double> d_slots_, r_slots_;
};

}  // namespace hybridtest::runner
