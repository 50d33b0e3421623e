#pragma once
// HybridTest: the loop policy of a (hybrid) simulation — the paper's Algorithm 1 with all s
// stages. For each step n:
//
//   for each stage i = 0..s−1 (ExplicitRungeKutta::Step):
//     x_i = x_n + h Σ_j a_ij k_j                         pure
//     d   = slot displacements at x_i                    pure (the model's slot fields)
//     r   = substructures.Trial(d)                       ◄ the impure seam: steel moves here
//     if i == 0: substructures.Commit(); journal row n   (x_0 = x_n: the committed state)
//     k_i = f_rhs(t_n + c_i h, x_i, r)                   pure (Kane engine)
//   x_{n+1} = x_n + h Σ b_i k_i
//
// and a last trial at x_N completes the last row. Row n of the journal therefore holds the
// committed state x_n and the restoring forces measured at exactly that state; it is on disk
// before stage 1 of step n moves anything.
//
// On any failure (SafetyStop, TransferError, a singular mass matrix, a write error) every
// physical substructure is put on Hold(), every committed state is in the journal (the row of
// the current state with NaN restoring forces if its trial failed), the sidecar records the
// status and the statistics, and the error propagates to the caller. Nothing is retried.
#include <string>

#include "hybridtest/runner/progress.h"
#include "hybridtest/runner/run_record.h"

namespace hybridtest::runner {

struct RunOptions {
  std::string csv_path;           // journal path
  std::string command = "run";    // recorded in the sidecar
  ProgressOptions progress;       // mode kQuiet to silence
  bool record_stages = true;      // also write <run>.stages.csv when a physical slot exists
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

  const io::SimulationConfig& cfg_;
  nlohmann::json stiffness_record_ = nlohmann::json::array();
  SubstructureList subs_;
  RunOptions options_;
  RunStatistics stats_;
};

// Journal path for a run: --out if given, else the config's output.csv, else
// results/<config name>.csv.
std::string ResolveOutputPath(const io::SimulationConfig& cfg, const std::string& out_option);

}  // namespace hybridtest::runner
