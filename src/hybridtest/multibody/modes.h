#pragma once
// Natural modes of a model about an operating point: the state matrix in the independent
// states (assembly.h, LinearizeConstrained), its eigenvalues λ, and per mode the natural
// frequency |λ|/2π [Hz], the damped frequency |Im λ|/2π [Hz], the damping ratio −Re λ/|λ|
// (1 for a real negative λ, −1 for a real positive one, 0 for λ = 0) and the mode shape (the
// eigenvector, scaled so that its largest entry is 1).
//
// Restoring-force slots are closed by their default numerical substructure, r = k d(q) (the
// model's slot stiffnesses), so a specimen's stiffness moves the modes as in the test.
#include <complex>
#include <string>
#include <vector>

#include "hybridtest/multibody/assembly.h"

namespace hybridtest::multibody {

struct Mode {
  std::complex<double> eigenvalue;       // [1/s]
  double frequency_hz = 0.0;             // |λ| / 2π
  double damped_frequency_hz = 0.0;      // |Im λ| / 2π
  double damping_ratio = 0.0;            // −Re λ / |λ|
  Eigen::VectorXcd shape;                // (independent states), largest entry 1
};

struct ModeAnalysis {
  Eigen::VectorXd x;                     // the operating point, assembled (2n + nz)
  Linearization linearization;
  std::vector<Mode> modes;               // by ascending |λ|, then Im λ
};

// Linearises at (t, x) after assembling x (dependent q and u solved), with r = k d(q) for the
// `slot_stiffness` k (one per slot [N/m or N·m/rad]; empty: r = 0).
ModeAnalysis CalcModes(const Model& model, double t, const Eigen::VectorXd& x,
                       const std::vector<double>& slot_stiffness);

}  // namespace hybridtest::multibody
