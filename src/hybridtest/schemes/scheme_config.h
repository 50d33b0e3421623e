#pragma once
// SchemeConfig: the `integrator:` section of a run config, as data (parsed and validated in
// io/config.cc), and MakeScheme, which builds the scheme it names.
//
//   integrator:
//     scheme: runge-kutta     # runge-kutta (default) | alpha-os | mr-os
//     tableau: heun           # runge-kutta: a catalogue name or a user tableau
//     dt: 0.001               # [s] the step (runge-kutta, fixed alpha-os), or the first step
//     alpha: -0.05            # alpha-os: α ∈ [−1/3, 0] (numerical damping of high modes)
//     adaptive:               # alpha-os, mr-os: choose the next step from an error estimate
//       tolerance: 2.0e-6     # [m] local error per step (slot displacement units)
//       dt_min: 0.001         # [s]
//       dt_max: 0.2           # [s]
//     substep: 0.001          # mr-os: largest RK4 substep of the numerical model [s]
#include <Eigen/Core>

#include <memory>
#include <string>

#include "hybridtest/integrators/butcher_tableau.h"
#include "hybridtest/multibody/model.h"
#include "hybridtest/schemes/hybrid_scheme.h"

namespace hybridtest::schemes {

enum class SchemeKind { kRungeKutta, kAlphaOs, kMrOs };

struct AdaptiveStep {
  bool enabled = false;
  double tolerance = 2.0e-6;  // local error target per step. Unit: slot displacement [m]
  double dt_min = 1.0e-3;     // [s]
  double dt_max = 0.2;        // [s]
};

// The scheme-specific part; the tableau, dt, duration and step count stay where they were
// (io::SimulationConfig) and are passed to MakeScheme.
struct SchemeConfig {
  SchemeKind kind = SchemeKind::kRungeKutta;
  double alpha = -0.05;                 // kAlphaOs: α ∈ [−1/3, 0]
  AdaptiveStep adaptive;                // kAlphaOs, kMrOs
  double substep = 1.0e-3;              // kMrOs: largest numerical substep. Unit: [s]
};

// "runge-kutta", "alpha-os", "mr-os".
std::string SchemeKindName(SchemeKind kind);

// What a scheme may know about the substructures besides the model: per slot (m),
//   k0              initial stiffness K0 [N/m] or [N·m/rad] (physical: configured or measured;
//                   numerical: from its law);
//   max_increment   largest change of the slot displacement between two specimen evaluations
//                   that the safety limits allow [m] (+inf for a numerical slot);
//   k0_matrix       the coupled K0 (m × m) [N/m] where a substructure serves several slots
//                   (its diagonal is k0); empty when every slot's K0 is its own (diag(k0)).
struct SlotInfo {
  Eigen::VectorXd k0;
  Eigen::VectorXd max_increment;
  Eigen::MatrixXd k0_matrix;
};

// Builds the configured scheme for `model` (which must outlive it). Throws ConfigError when
// the scheme cannot serve this model (e.g. α-OS needs q̇ = u).
//   tableau    kRungeKutta's tableau
//   dt         the step (fixed), or the first step (adaptive). Unit: [s]
//   duration   simulated time from t0 = 0. Unit: [s]
//   steps      duration / dt (fixed-step schemes take exactly this many)
std::unique_ptr<HybridScheme> MakeScheme(const SchemeConfig& config,
                                         const integrators::ButcherTableau& tableau, double dt,
                                         double duration, long steps,
                                         const multibody::Model& model, const SlotInfo& slots);

}  // namespace hybridtest::schemes
