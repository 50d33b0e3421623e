#pragma once
// HybridTest: the loop policy of a (hybrid) simulation. It owns the substructures, the
// journal (and stage record), the run state and the progress display, and drives any
// schemes::HybridScheme (decision 0010):
//
//   activate the substructures; measure K0 where the config asks for it
//   r_0 = trial at x_0 (step 0, stage 0); commit; journal row 0       ◄ steel moves here
//   until the scheme is finished:
//     scheme.Step(seam, rows)     the scheme's trials go through the seam: slot displacements
//                                 d(t, q) of the state it names → substructures.Trial(d) → r;
//                                 a stage record row per trial; intermediate rows (MR-OS's
//                                 substeps, no specimen sample) go to the journal
//     substructures.Commit(); run state saved; journal row of the committed point (t, x, r)
//                                 with the last exchange of each physical substructure
//
// For explicit Runge–Kutta this is the paper's Algorithm 1 with all s stages, trial for trial
// as before hybrid schemes (the trial at x_{n+1} is the stage 0 of step n+1): row n holds the
// committed state x_n and the forces measured at exactly that state, on disk before the next
// trial moves anything.
//
// On any failure (SafetyStop, TransferError, a singular mass matrix, a write error) every
// physical substructure is put on Hold(), every committed state is in the journal (plus the
// state an explicit RK step computed, with NaN restoring forces, if its own trial failed), the
// sidecar records the status and the statistics, and the error propagates to the caller.
// Nothing is retried; `hybridtest resume` continues from the run state (decision 0011).
#include <functional>
#include <string>

#include "hybridtest/schemes/hybrid_scheme.h"

#include "hybridtest/runner/progress.h"
#include "hybridtest/runner/run_record.h"
#include "hybridtest/runner/run_state.h"

namespace hybridtest::runner {

struct RunOptions {
  std::string csv_path;           // journal path
  std::string command = "run";    // recorded in the sidecar
  ProgressOptions progress;       // mode kQuiet to silence
  bool record_stages = true;      // also write <run>.stages.csv when a physical slot exists
  bool save_state = true;         // write <run>.state.json (run_state.h) for `resume`
  // Resume (`hybridtest resume`, docs/safety.md): continue from this state instead of starting
  // at x0, appending to the reopened journal and stage record; nullptr for a new run.
  const RunState* resume_from = nullptr;
  double resume_force_tolerance = 0.0;  // [N]; <= 0: 1 % of each physical slot's force_hard
  nlohmann::json resume_record = nlohmann::json::object();  // e.g. time, previous stop
  double resume_position_tolerance = 0.0;  // [m]; <= 0: derived per slot (physical_substructure.h)
  // The files the run reads, [{role, path (relative to the journal's directory), sha256}]:
  // recorded in the sidecar and in every run state; resume checks them (docs/safety.md).
  nlohmann::json inputs = nlohmann::json::array();
};

struct RunStatistics {
  long steps = 0;                 // committed steps
  long rows = 0;                  // journal rows written
  long physical_evaluations = 0;  // trials sent to benches
  double sim_time = 0.0;          // simulated time reached [s]
  double wall_time = 0.0;         // [s]
  double lab_time = 0.0;          // lab time reported by the benches [s]
  double slowdown = 0.0;          // lab time / simulated time (0 without a bench) [-]
  double wall_slowdown = 0.0;     // wall time / simulated time [-]
};

class HybridTest {
 public:
  HybridTest(const io::SimulationConfig& cfg, SubstructureList substructures, RunOptions options);
  // Runs to the end. Throws the failure (after writing everything, see above).
  RunStatistics Run();
  const RunStatistics& statistics() const { return stats_; }

 private:
  // Measures K0 on every physical substructure whose config asks for it (a slow ramp before
  // the test) and records every slot's K0 and its source for the sidecar.
  void MeasureRequestedStiffness();
  // Resume: restores every substructure and the scheme from the state, writes the state's
  // committed row if a crash lost it, re-imposes the last committed command on each physical
  // slot (stage record: stage −2 ramp moves, −1 the re-imposition) and records the resume in
  // the sidecar's "resumes" array. Throws SafetyStop if a force check fails.
  // Restores every substructure's state (before the scheme is made: K0 may be measured).
  void RestoreSubstructures(const RunState& state);
  // write_row(): journals the scheme's committed point with the last exchanges;
  // stage_row(step, stage, t): appends the last exchanges to the stage record.
  void ResumeFrom(const RunState& state, schemes::HybridScheme& scheme, io::Journal& journal,
                  const std::function<void()>& write_row,
                  const std::function<void(long, int, double)>& stage_row);
  // The state to save after the commit of `scheme`'s point, which will be row `rows` − 1.
  RunState CaptureState(const schemes::HybridScheme& scheme, long rows, long stage_rows,
                        const nlohmann::json& statistics) const;

  const io::SimulationConfig& cfg_;
  nlohmann::json stiffness_record_ = nlohmann::json::array();
  SubstructureList subs_;
  RunOptions options_;
  RunStatistics stats_;
  double wall_offset_ = 0.0;  // wall time of the sessions before a resume [s]
  long rows_cut_ = 0;         // resume: journal rows after the state's, cut before reopening
};

// Journal path for a run: --out if given, else the config's output.csv, else
// results/<config name>.csv.
std::string ResolveOutputPath(const io::SimulationConfig& cfg, const std::string& out_option);

}  // namespace hybridtest::runner
