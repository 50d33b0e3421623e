#pragma once
// The journal's constraint-force channels (run_record.h): the multipliers λ of the constraints
// that record their force (ConstraintSpec::record_force), evaluated at a row's state from the
// model alone (multibody/constraints.h CalcConstraintForces). It uses its own engine scratch,
// so the scheme's numbers are untouched and a row costs one constrained right-hand side.
#include <Eigen/Core>

#include <vector>

#include "hybridtest/multibody/data.h"

namespace hybridtest::runner {

class ConstraintForceRecorder {
 public:
  explicit ConstraintForceRecorder(const multibody::Model& model);

  // The number of channels (0: the model records no constraint force).
  int size() const { return static_cast<int>(rows_.size()); }
  // Writes the recorded λ at (t [s], x, r [N]) to out[0..size()). A state where the
  // constrained equations cannot be solved gives NaN (the scheme reports that state itself).
  // Allocation-free.
  void Fill(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& r, double* out);

 private:
  const multibody::Model& model_;
  std::vector<int> rows_;
  multibody::Data<double> data_;
  Eigen::VectorXd xdot_, lambda_;
};

}  // namespace hybridtest::runner
