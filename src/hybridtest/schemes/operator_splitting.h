#pragma once
// OperatorSplittingScheme: what the operator-splitting schemes (alpha_os.h, mr_os.h) share —
// one specimen evaluation per step, the initial stiffness K0 of every slot (required), a fixed
// or adaptive step (step_control.h) towards the end of the run, and the memory of the last
// command's slot displacements (for the increment check before the specimen moves).
#include <string>

#include "hybridtest/multibody/data.h"
#include "hybridtest/multibody/model.h"
#include "hybridtest/schemes/hybrid_scheme.h"
#include "hybridtest/schemes/scheme_config.h"
#include "hybridtest/schemes/stability_guard.h"

namespace hybridtest::schemes {

class OperatorSplittingScheme : public HybridScheme {
 public:
  int evaluations_per_step() const override { return 1; }
  bool finished() const override;
  double next_step_size() const override { return h_; }

 protected:
  // dt [s]: the step (fixed) or the first step (adaptive, clamped to [dt_min, dt_max]);
  // `steps` = duration / dt when fixed. Throws ConfigError naming the slot and the fix when a
  // slot has no finite K0. `stability_constant`: the scheme's c of stability_guard.h.
  OperatorSplittingScheme(const multibody::Model& model, const SchemeConfig& config,
                          const SlotInfo& slots, double dt, double duration, long steps,
                          double stability_constant);

  // "fixed step 0.005 s" or "adaptive step 0.001–0.05 s, tolerance 1e-06 m".
  std::string StepDescription() const;
  // The step to take next [s] and the time it ends at [s]: fixed steps land on (n+1)·dt
  // exactly; adaptive ones on the end of the run.
  double StepToTake() const;
  double StepEnd(double h) const;

  // Adaptive steps, once the step's point is committed: after a step of size h [s] that
  // imposed d (m) and measured r (m), with the local error estimate e [m] and
  // the step controller's choice h_next [s], sets the next step h_ within the stability
  // guard's bound (stability_guard.h).
  void ChooseNextStep(double h, double h_next, double e, const Eigen::VectorXd& d,
                      const Eigen::VectorXd& r);

  // The shared memory (h, K0, last command, stability guard) into/from the scheme's own state.
  void SaveSplittingState(nlohmann::json& state) const;
  void RestoreSplittingState(const nlohmann::json& state);

  // K0 is the coupled matrix SlotInfo::k0_matrix (else diag(k0)). The stability guard sees
  // its diagonal.
  bool coupled() const { return slots_.k0_matrix.size() > 0; }

  const multibody::Model& model_;
  SchemeConfig config_;
  SlotInfo slots_;
  double h_;          // next step [s]
  double duration_;   // [s]
  long steps_;        // fixed steps
  int n_, m_;
  multibody::Data<double> data_;
  Eigen::VectorXd d_last_;  // (m) slot displacements of the last command [m]
  StabilityGuard guard_;
};

}  // namespace hybridtest::schemes
