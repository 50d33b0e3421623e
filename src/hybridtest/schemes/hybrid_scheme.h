#pragma once
// HybridScheme: how a hybrid test advances from one committed state to the next (the loop
// policy's step; the runner owns the loop, the journal and the substructures).
//
// A hybrid model is M(q) u̇ = g(t, q, u, r), q̇ = W(q) u, x = [q; u] (2n), where r (m) are the
// static restoring forces of the substructures. A scheme computes committed points
// (t_n, x_n, r_n) one step at a time. Its only access to the substructures is the seam:
//
//   seam.Trial({step, stage, t}, d, r)  every substructure is tried at the slot displacements
//                                       d (m), which the scheme computed from its state as
//                                       d(t, q): a physical one MOVES STEEL here.
//
// Contract (every scheme, tested in tests/schemes/):
//   - a step makes exactly evaluations_per_step() trials, never two at the same trial state
//     on purpose, and is never redone: a finished step is final (the specimen cannot be
//     un-moved), so an adaptive scheme chooses the NEXT step size from an error estimate and
//     never rejects the current one;
//   - the runner tries x_0 once before Start() (that trial is committed and journalled as row
//     0), then calls Step() until finished(); after each Step() it commits the substructures
//     and journals (t(), x(), r()) with the last exchange of each physical substructure;
//   - a step may emit intermediate committed rows (e.g. the substeps of a multi-rate scheme)
//     through RowSink before it returns; they carry no specimen sample;
//   - SaveState()/RestoreState() capture everything the scheme needs to continue a run after
//     a crash (the committed point and the scheme's own memory: previous samples, step size,
//     K0); restoring and stepping gives bit-identical results to not stopping.
//
// Units: t [s]; x SI per coordinate; r [N] (or [N·m] for a rotational slot); K0 [N/m]
// (or [N·m/rad]).
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <limits>
#include <string>

namespace hybridtest::schemes {

// Where a trial belongs, for records and messages: the trial is part of step `step` (stage 0
// is the trial at a committed state), at model time t [s].
struct TrialPoint {
  long step = 0;
  int stage = 0;
  double t = 0.0;  // [s]
};

// The impure seam, implemented by the runner's Session.
class SubstructureSeam {
 public:
  virtual ~SubstructureSeam() = default;
  // Tries every substructure at the slot displacements d (m; [m] or [rad] per slot) and writes
  // their restoring forces into r (m; [N] or [N·m]). Throws SafetyStop or TransferError from a
  // physical substructure.
  virtual void Trial(const TrialPoint& at, const Eigen::VectorXd& d,
                     Eigen::Ref<Eigen::VectorXd> r) = 0;
};

// Where a step's intermediate committed rows go (the runner's journal).
class RowSink {
 public:
  virtual ~RowSink() = default;
  // A committed state between two specimen samples: time [s], x (2n), r (m) as the scheme
  // modelled them (no specimen measurement belongs to this row).
  virtual void Row(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& r) = 0;
};

// A seam or a row sink made from a callable (the runner's lambdas; tests' fakes).
template <class F>
class SeamOf final : public SubstructureSeam {
 public:
  explicit SeamOf(F f) : f_(std::move(f)) {}
  void Trial(const TrialPoint& at, const Eigen::VectorXd& d,
             Eigen::Ref<Eigen::VectorXd> r) override {
    f_(at, d, r);
  }

 private:
  F f_;
};
template <class F>
class RowSinkOf final : public RowSink {
 public:
  explicit RowSinkOf(F f) : f_(std::move(f)) {}
  void Row(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& r) override { f_(t, x, r); }

 private:
  F f_;
};

// A committed point of the run.
struct CommittedPoint {
  long step = 0;        // steps committed since t0 (0 at the start)
  double t = 0.0;       // [s]
  Eigen::VectorXd x;    // (2n) [q; u]
  Eigen::VectorXd r;    // (m) restoring forces the scheme used at (t, x)
};

class HybridScheme {
 public:
  virtual ~HybridScheme() = default;
  HybridScheme(const HybridScheme&) = delete;
  HybridScheme& operator=(const HybridScheme&) = delete;

  // Short name as in configs ("heun", "alpha-os", "mr-os") and a one-line description.
  virtual std::string name() const = 0;
  virtual std::string Describe() const = 0;

  // Specimen evaluations (seam trials) one step makes.
  virtual int evaluations_per_step() const = 0;

  // Begins at the committed initial point: x0 (2n) at t0 [s], r0 (m) measured there.
  void Start(double t0, const Eigen::VectorXd& x0, const Eigen::VectorXd& r0);

  // One step from the committed point to the next (see the contract above).
  virtual void Step(SubstructureSeam& seam, RowSink& rows) = 0;

  // True once the committed time has reached the end of the run.
  virtual bool finished() const = 0;

  // The last committed point.
  const CommittedPoint& committed() const { return point_; }

  // A state the last step computed but could not commit because its own trial failed (an
  // explicit Runge–Kutta step tries x_{n+1} as the stage 0 of the next step); nullptr if none.
  // The runner journals it with NaN restoring forces, for the operator's information.
  const CommittedPoint* uncommitted() const { return has_uncommitted_ ? &uncommitted_ : nullptr; }

  // Size of the next step [s] (adaptive schemes change it after every step).
  virtual double next_step_size() const = 0;

  // Estimated number of steps still to go (progress display; exact for fixed steps).
  long EstimatedStepsLeft(double t_end) const;

  // Everything needed to continue: the committed point and the scheme's own memory.
  nlohmann::json SaveState() const;
  // Restores what SaveState() wrote. Throws hybridtest::Error if it does not fit this scheme
  // (another scheme, other sizes).
  void RestoreState(const nlohmann::json& state);

 protected:
  // state_size = 2n, num_slots = m.
  HybridScheme(int state_size, int num_slots);
  // Called by Start() once the committed point is set.
  virtual void OnStart() {}
  // The scheme's own memory beyond the committed point.
  virtual nlohmann::json SaveOwnState() const { return nlohmann::json::object(); }
  virtual void RestoreOwnState(const nlohmann::json& /*state*/) {}

  CommittedPoint point_;
  CommittedPoint uncommitted_;
  bool has_uncommitted_ = false;
};

// A vector as a JSON array and back (exact: doubles are written with round-trip precision).
nlohmann::json ToJson(const Eigen::VectorXd& v);
Eigen::VectorXd VectorFromJson(const nlohmann::json& j, Eigen::Index expected_size,
                               const char* what);

}  // namespace hybridtest::schemes
