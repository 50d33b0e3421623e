// See step_control.h.
#include "hybridtest/schemes/step_control.h"

#include "hybridtest/multibody/kane.h"

namespace hybridtest::schemes {

void CalcSlotJacobian(const multibody::Model& model, multibody::Data<double>& data, double t,
                      const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::MatrixXd& D,
                      Eigen::VectorXd& q_scratch,
                      Eigen::VectorXd& d_plus, Eigen::VectorXd& d_minus) {
  const Eigen::Index n = q.size();
  D.resize(model.num_slots(), n);
  q_scratch = q;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double step = 1e-6 * std::max(1.0, std::abs(q(j)));
    q_scratch(j) = q(j) + step;
    multibody::CalcSlotDisplacements<double>(model, data, t, q_scratch, d_plus);
    q_scratch(j) = q(j) - step;
    multibody::CalcSlotDisplacements<double>(model, data, t, q_scratch, d_minus);
    q_scratch(j) = q(j);
    D.col(j) = (d_plus - d_minus) / (2.0 * step);
  }
}

double IncrementRatio(const Eigen::VectorXd& d_new, const Eigen::VectorXd& d_old,
                      const Eigen::VectorXd& max_increment) {
  double worst = 0.0;
  for (Eigen::Index s = 0; s < d_new.size(); ++s) {
    if (std::isfinite(max_increment(s)) && max_increment(s) > 0.0) {
      worst = std::max(worst, std::abs(d_new(s) - d_old(s)) / max_increment(s));
    }
  }
  return worst;
}

}  // namespace hybridtest::schemes
