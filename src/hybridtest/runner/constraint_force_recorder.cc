// See constraint_force_recorder.h.
#include "hybridtest/runner/constraint_force_recorder.h"

#include <limits>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/runner/run_record.h"

namespace hybridtest::runner {

ConstraintForceRecorder::ConstraintForceRecorder(const multibody::Model& model)
    : model_(model),
      rows_(RecordedConstraintRows(model)),
      data_(model),
      xdot_(model.num_states()),
      lambda_(model.num_constraint_rows()) {}

void ConstraintForceRecorder::Fill(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& r,
                                   double* out) {
  if (rows_.empty()) return;
  try {
    multibody::CalcStateDerivative<double>(model_, data_, t, x, r, xdot_);
    multibody::CalcConstraintForces(model_, data_, lambda_);
  } catch (const ModelError&) {
    for (std::size_t k = 0; k < rows_.size(); ++k) out[k] = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  for (std::size_t k = 0; k < rows_.size(); ++k) out[k] = lambda_(rows_[k]);
}

}  // namespace hybridtest::runner
