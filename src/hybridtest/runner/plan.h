#pragma once
// Planning a hybrid test the day before: which scheme and step buy the required accuracy
// with the fewest specimen evaluations? `hybridtest plan CONFIG` runs the configured test,
// with candidate schemes, against emulated specimens only (never a real bench), and compares
// every run with a fine numerical reference.
//
// Reference: the same model with every physical slot replaced by a numerical substructure of
// its emulated specimen's law seen through the slot's setup (scale, signs, p0, load-cell zero;
// for the default cantilever bench: the linear 5,250 N/m spring, i.e. the paper's rotor with
// blade1.k_b = 5250), integrated with RK4 at h = 0.1 ms.
//
// Error of a run (the definition of the lab-time study, docs/lab-time.md):
//   e = max over every slot s and every journal row k of |d_s(t_k) − d_s,ref(t_k)|
//       / (peak-to-peak of the first physical slot's d_ref over t ∈ [0.2 T, T])
// with d the slot displacements (q1..q3 for the rotor), d_ref interpolated linearly to the
// row times; T the duration (so [2, 10] s for the paper's 10 s).
//
// Lab time: as the emulated bench's clock reports it (calibrated to the paper's bench).
// Reversals: how often the commanded actuator motion changes direction (every trial); force
// reversals: how often the specimen force reversed within a move (an overshooting actuator;
// the stage record's <slot>_force_reversals), summed over the run.
//
// Noise seeds: where an emulated bench has load-cell noise, every candidate runs once per seed
// of PlanOptions::seeds (the bench's `seed` replaced) and its row reports the worst run: the
// largest error, evaluations and lab time, and a failure if any seed failed.
//
// Before the candidates, the reference is checked against every physical slot's safety
// limits (stroke, force_soft, force_hard, at the setup's actuator coordinates): a limit that
// the reference itself exceeds would stop every candidate, so plan says so up front.
//
// Every run is a Session held in memory (a recorder observer keeps its rows and commands):
// plan writes no file unless PlanOptions::work_dir asks for them.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/io/run_spec.h"
#include "hybridtest/io/run_reader.h"

namespace hybridtest::runner {

struct PlanCandidate {
  std::string label;                   // e.g. "mr-os adaptive, tol 2e-06 m"
  schemes::SchemeConfig scheme;
  integrators::ButcherTableau tableau; // runge-kutta only
  double dt = 0.0;                     // [s]
};

struct PlanResult {
  PlanCandidate candidate;
  bool ok = false;               // the run completed
  std::string failure;           // why not, if !ok
  long evaluations = 0;          // specimen evaluations (incl. a K0 ramp)
  double lab_time = 0.0;         // [s]
  double error = 0.0;            // relative, see above [-]
  long reversals = 0;            // direction reversals of the first physical command
  long force_reversals = 0;      // reversals of the specimen force within moves, all slots
  double wall_time = 0.0;        // [s]
  int runs = 0;                  // noise seeds run (the row is the worst of them)
};

// A safety limit that the reference reaches: every candidate would stop there.
struct PlanWarning {
  std::string slot;       // e.g. "r1"
  std::string limit;      // "stroke_max", "stroke_min", "force_soft" or "force_hard"
  double value = 0.0;     // the reference's value at t [m] or [N]
  double limit_value = 0.0;  // [m] or [N]
  double t = 0.0;         // first time the reference exceeds it [s]
  std::string message;    // one line naming all of the above and what to do
};

struct PlanOptions {
  double tolerance = 0.01;                   // largest acceptable error [-]
  std::optional<std::string> emulate_bench;  // stand-in bench for non-emulated physical slots
  std::string work_dir;                      // also write every run's files here (empty:
                                             // nothing is written; runs are held in memory)
  // work_dir: each run is opened through the front door (runner/open_run.h), as `run` opens
  // one: an earlier plan's files there are replaced only with overwrite; command_line goes
  // into each run's provenance.
  bool overwrite = false;
  std::string command_line;
  std::vector<unsigned long> seeds = {1, 2, 3};  // load-cell noise seeds per candidate
  // Called once after the reference with the limits it exceeds (possibly none).
  std::function<void(const std::vector<PlanWarning>&)> on_warnings;
  // Called after each candidate (index, count, result) for progress output.
  std::function<void(std::size_t, std::size_t, const PlanResult&)> on_result;
};

// The candidates for spec: the configured scheme first, the paper's scheme (Heun at 1 ms, a
// specimen evaluation at each of its two stages) as a baseline unless it is the configured one,
// then α-OS (fixed and adaptive) and
// MR-OS (fixed and adaptive) over a range of steps and tolerances scaled to the reference's
// peak-to-peak `p2p` [m].
std::vector<PlanCandidate> DefaultCandidates(const io::RunSpec& spec, double p2p);

// Relative error of `run` against `reference` (definition above); `first_physical_slot` is
// the slot whose peak-to-peak normalises it. Throws IoError if a channel is missing.
double RelativeError(const multibody::Model& model, const io::RunData& run,
                     const io::RunData& reference, int first_physical_slot, double* p2p = nullptr);

// Runs the reference and every candidate; returns the results in candidate order. Throws
// ConfigError if cfg has no physical slot, or one whose bench is not emulated and no
// emulate_bench is given.
std::vector<PlanResult> PlanTest(const io::RunSpec& spec, const PlanOptions& options);

// The safety limits of the physical slots of `spec` that the reference run exceeds (see above).
std::vector<PlanWarning> ReferenceLimitWarnings(const io::RunSpec& spec,
                                                const io::RunData& reference);

// One line for the closing advice when a candidate reversed the specimen force within moves
// (`result.force_reversals` > 0): the cause (an overshooting actuator) and the fix
// (`actuator.approach: monotone` on an emulated bench, a monotone final approach on a real
// controller); "" when it did not.
std::string ForceReversalAdvice(const PlanResult& result);

// `spec` once per seed, every emulated bench with load-cell noise given that seed in place of
// its own; a spec without such a bench comes back once, unchanged.
std::vector<io::RunSpec> SeededSpecs(const io::RunSpec& spec,
                                     const std::vector<unsigned long>& seeds);

// The cheapest result (fewest evaluations, then lab time) with error ≤ tolerance, if any.
std::optional<PlanResult> Recommend(const std::vector<PlanResult>& results, double tolerance);

// The `integrator:` section that selects a candidate, as YAML text.
std::string IntegratorYaml(const PlanCandidate& candidate);

}  // namespace hybridtest::runner
