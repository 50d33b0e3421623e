#pragma once
// Shared pieces of the operator-splitting schemes (alpha_os.h, mr_os.h).
//
// Step-size control without rejection: after a step with local error estimate e (same unit as
// the tolerance), the NEXT step is
//
//   h_next = clip( h · clip( 0.9 (tol / e)^(1/p), 0.5, 2 ), dt_min, dt_max )
//
// with p the order of the estimate in h (3 for both schemes here). The step just taken is
// never redone: a physical specimen cannot be un-moved.
//
// Safety-aware prediction: before a specimen is moved, a scheme may shorten the step it is
// about to take (nothing has moved yet) so that the predicted change of every slot
// displacement stays within `kIncrementMargin` of the slot's max_increment; otherwise the
// safety monitor would refuse the command and stop the test.
#include <Eigen/Core>

#include <algorithm>
#include <cmath>

#include "hybridtest/multibody/data.h"
#include "hybridtest/multibody/model.h"
#include "hybridtest/schemes/scheme_config.h"

namespace hybridtest::schemes {

inline constexpr double kIncrementMargin = 0.8;  // fraction of max_increment a step may use

// The next step size from the error estimate e of a step of size h (see above).
inline double NextStepSize(const AdaptiveStep& a, double h, double e, double order) {
  const double factor =
      e > 0.0 ? std::clamp(0.9 * std::pow(a.tolerance / e, 1.0 / order), 0.5, 2.0) : 2.0;
  return std::clamp(h * factor, a.dt_min, a.dt_max);
}

// The step to take from t towards t_end: h, shortened to land exactly on t_end (and
// stretched to t_end when less than half a minimal step would remain).
inline double StepTowards(double t, double t_end, double h, double dt_min) {
  const double left = t_end - t;
  if (h >= left || left - h < 0.5 * dt_min) return left;
  return h;
}

// D = ∂d/∂q (m × n) at (t, q): the slot displacements' sensitivity to the coordinates, by
// central differences (exact for the affine slot fields of most models to rounding).
// d_scratch: (m) workspaces; no allocation once D has its size.
void CalcSlotJacobian(const multibody::Model& model, multibody::Data<double>& data, double t,
                      const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::MatrixXd& D,
                      Eigen::VectorXd& q_scratch,
                      Eigen::VectorXd& d_plus, Eigen::VectorXd& d_minus);

// Largest |d_new − d_old| / max_increment over the slots with a finite max_increment.
double IncrementRatio(const Eigen::VectorXd& d_new, const Eigen::VectorXd& d_old,
                      const Eigen::VectorXd& max_increment);

}  // namespace hybridtest::schemes
